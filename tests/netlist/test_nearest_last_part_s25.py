"""'Did you mean' for a name without a dot also looks at each dotted name's last part: ``zeta2`` written
for a valve's damping ratio suggested ``ret.A`` (three letters in five alike) and not ``relief.zeta``."""

from __future__ import annotations

from blocks.units import nearest

NAMES = ["p_set", "k_s", "relief.p_set", "relief.k_s", "relief.u_z", "relief.zeta", "ret.A", "fluid.beta"]


def test_an_undotted_name_finds_a_component_parameter_by_its_last_part():
    assert nearest("zeta2", NAMES)[0] == "relief.zeta"


def test_a_tie_goes_to_the_whole_names_likeness():
    assert nearest("k_z", NAMES) == ["k_s"]
    assert nearest("p_sett", NAMES) == ["p_set", "relief.p_set"]


def test_a_short_last_part_alike_by_chance_is_not_suggested():
    """'dp_t' is 3 letters in 10 like 'p_sett' (ratio 0.6): a whole name at 0.6 is suggested, a last part not."""
    assert "ret.dp_t" not in nearest("p_sett", NAMES + ["ret.dp_t"])


def test_a_dotted_name_is_compared_whole():
    assert nearest("relif.zeta", NAMES)[0] == "relief.zeta"


def test_a_name_differing_in_case_comes_first():
    assert nearest("P_SET", NAMES)[0] == "p_set"
