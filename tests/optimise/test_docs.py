"""The job file's format is in the generated netlist reference (from blocks.optimise.job's docstring), every
key of the schema with it; and the docs name only commands that exist."""

import re
from pathlib import Path

from blocks import docs
from blocks.optimise.job import METHODS, CostSpec, FreeParameter, JobFile, SweepRange, SweepSpec, TermSpec

ROOT = Path(__file__).resolve().parents[2]


def job_section() -> str:
    text = docs.reference_text()
    assert "## The optimisation job file" in text
    return text.split("## The optimisation job file", 1)[1].split("\n## ", 1)[0]


def test_every_key_of_a_job_file_is_in_the_reference():
    section = job_section()
    keys = {name for model in (JobFile, CostSpec, TermSpec, FreeParameter, SweepSpec, SweepRange)
            for name in model.model_fields}
    missing = sorted(k for k in keys if f"{k}:" not in section)
    assert not missing, f"job keys missing from the reference's example: {missing}"
    settings = {name for spec in METHODS.values() for name in spec.model_fields} - {"method"}
    missing = sorted(k for k in settings if not re.search(rf"\b{k}\b", section))
    assert not missing, f"method settings missing from the reference: {missing}"
    for method in METHODS:
        assert f"{method}:" in section
    assert "constraints" in section  # what to do instead


def test_the_docs_name_only_existing_commands():
    """Review: the reference named a `vphs compare` command, which does not exist (`vphs diff` compares)."""
    import cli

    commands = set(cli.COMMANDS)
    sources = [docs.reference_text(), (ROOT / "README.md").read_text()]
    sources += [p.read_text() for p in (ROOT / "blocks").rglob("*.py")] + [(ROOT / "cli.py").read_text()]
    named = {m for text in sources for m in re.findall(r"`vphs ([a-z_]+)\b", text)}
    assert named and not named - commands, f"commands that do not exist: {sorted(named - commands)}"
