"""Job files for tests, on the drive line: ``drive_line_job(tmp_path, "name", {"Kp": "{min: 1, max: 3}"},
"{method: complex, max_evaluations: 20}")`` writes <folder>/name.yaml with its output folder <folder>/name
and one cost term, the position error in mm."""

from pathlib import Path

DRIVE_LINE = Path(__file__).resolve().parents[2] / "netlists" / "opt" / "drive_line.yaml"


def drive_line_job(folder: Path, name: str, parameters: dict[str, str], algorithm: str, extra: str = "",
                   seed: int = 2) -> Path:
    """The job file's path; ``parameters``: name -> its flow-style entry; ``extra``: more YAML (a sweep:)."""
    lines = [f"netlist: {DRIVE_LINE}", f"output: {folder / name}", f"seed: {seed}", "parameters:"]
    lines += [f"  {key}: {bounds}" for key, bounds in parameters.items()]
    lines += ["cost: {terms: {pos: {kind: ise, signal: x, reference: x_ref, unit: mm}}}", f"algorithm: {algorithm}"]
    path = folder / f"{name}.yaml"
    path.write_text("\n".join(lines) + "\n" + extra)
    return path
