"""Gap found by mutation testing blocks/optimise/repeats.py (session 27).

The rule (module docstring): a repeat's record copies the earlier one's parameters and outcome, "takes no
time (``seconds`` 0, no ``pids``) and says ``"repeat_of": <index of the evaluation simulated>``", keeping
its own index, x and step.
"""

import math

from blocks.optimise.repeats import Repeats, repeat_record


def original_record():
    return {"type": "evaluation", "id": "000003-aa", "index": 3, "x": [0.25, 0.5], "parameters": {"Kp": 2.0},
            "status": "ok", "cost": 12.5, "cases": {"nominal": {"cost": 12.5}}, "error": None, "warnings": ["w"],
            "seconds": 1.75, "pids": [4711], "step": "reflection", "iteration": 2, "n_rep": 0}


def test_a_repeat_takes_no_time_and_names_the_evaluation_simulated():
    """Built by hand from the rule: the outcome copied, seconds 0, pids [], repeat_of the original's index
    (and, for a repeat of a repeat, the index the first one names: the evaluation actually simulated)."""
    original = original_record()
    info = {"step": "retraction", "iteration": 4, "n_rep": 1}
    record = repeat_record(original, 9, "000009-bb", [0.25, 0.5], info)
    assert record == {"type": "evaluation", "id": "000009-bb", "index": 9, "x": [0.25, 0.5],
                      "parameters": {"Kp": 2.0}, "status": "ok", "cost": 12.5, "cases": {"nominal": {"cost": 12.5}},
                      "error": None, "warnings": ["w"], "step": "retraction", "iteration": 4, "n_rep": 1,
                      "seconds": 0.0, "pids": [], "repeat_of": 3}
    again = repeat_record(record, 12, "000012-cc", [0.25, 0.5], info)
    assert again["repeat_of"] == 3 and again["seconds"] == 0.0 and again["pids"] == []


def test_the_first_record_of_a_point_is_the_one_remembered_bit_for_bit():
    """'identical, bit for bit': the first record of x is kept; a point 1 ulp away is a new point."""
    repeats = Repeats()
    first = original_record()
    repeats.remember(first)
    repeats.remember({**first, "index": 5})
    assert repeats.original([0.25, 0.5]) is first
    assert repeats.original([0.25, math.nextafter(0.5, 1.0)]) is None
