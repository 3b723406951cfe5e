"""Benchmark: the Jacobian's sparsity pattern read per value a block returns against per block, in one run.

    python bench/jacobian_pattern.py [--repeats 15]

For each netlist the circuit is compiled once and simulated with each pattern in turn (the pattern and its
column groups are arrays the solver is given: blocks.compiler.structure.jacobian_pattern, per_output True or
False), alternating, the median time of each printed with the column groups, the right-hand-side calls per
run and the ratio. The runs must agree bit for bit (an entry a value does not read is 0 either way); a
difference is printed as FAIL and the exit code is 1.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from blocks.circuit import Circuit, _colour_columns  # noqa: E402
from blocks.compiler.structure import jacobian_pattern  # noqa: E402

NETLISTS = ("netlists/opt/bridge_travel.yaml", "netlists/bridge_crane/bridge_crane.yaml", "netlists/lga/lga.yaml",
            "netlists/rig/mcv_rig_multistep.yaml", "netlists/opt/drive_line.yaml",
            "netlists/components/servo_4wrle_step.yaml")


def _use(circuit, pattern) -> None:
    circuit.pattern = pattern
    circuit.groups, circuit.n_groups = _colour_columns(pattern)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()
    failed = False
    print(f"{'netlist':45s} {'states':>6s} {'groups':>13s} {'rhs calls':>15s} {'ms per run':>17s} {'ratio':>6s}")
    for netlist in NETLISTS:
        circuit = Circuit.from_file(ROOT / netlist, quiet=True)
        circuit.compile(quiet=True)
        patterns = {"value": jacobian_pattern(circuit.structure), "block": jacobian_pattern(circuit.structure, False)}
        times, results, groups = {k: [] for k in patterns}, {}, {}
        for _ in range(args.repeats + 1):  # the first round warms up and is not timed
            for kind, pattern in patterns.items():
                _use(circuit, pattern)
                groups[kind] = circuit.n_groups
                started = time.perf_counter()
                results[kind] = circuit.simulate()
                times[kind].append(time.perf_counter() - started)
        same = np.array_equal(results["value"].values, results["block"].values) and \
            np.array_equal(results["value"].states, results["block"].states)
        failed |= not same
        ms = {k: 1e3 * statistics.median(v[1:]) for k, v in times.items()}
        calls = {k: results[k].stats["rhs_calls"] for k in patterns}
        print(f"{netlist:45s} {circuit.structure.n_states:6d} {groups['block']:5d} -> {groups['value']:3d} "
              f"{calls['block']:7d} -> {calls['value']:5d} {ms['block']:7.2f} -> {ms['value']:6.2f} "
              f"{ms['value'] / ms['block']:6.2f}{'' if same else '  FAIL: results differ'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
