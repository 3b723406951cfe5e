"""The non-centrality lambda of a planted time-series effect with the command given by its levels and with
the command imposed as its recording (a latent trace): the chi^2 of the declared model fitted to the
noise-free truth (bench/calibrate_mc.py's truth, experiment and sizing, ``Setup.lam``; beside it the chi^2 of
the tool's own first fit, from one start), then whether the effect is accepted.

    python bench/recorded_lambda.py coulomb_friction@shaft 0.1657
    python bench/recorded_lambda.py transport_delay@u 0.000227
    python bench/recorded_lambda.py offlib_torque_pulse 0.6404     # the off-library effect: every candidate

A gap between the two lambdas is what the latent trace's knots absorb of the effect.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
import calibrate_mc as mc  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("effect", help="a place key of the time-series cases, e.g. coulomb_friction@shaft")
    parser.add_argument("value", type=float, help="its parameter value (SI)")
    args = parser.parse_args(argv)
    from blocks.calibrate.run import calibrate
    from blocks.circuit import Circuit

    for recorded in (False, True):
        mc.configure(None, recorded)
        s = mc.setup("time")
        off_library = args.effect.startswith("offlib_")  # the Monte Carlo's effect outside the library
        if args.effect not in s.places and not off_library:
            parser.error(f"{args.effect}: not a place of the drive line (e.g. {', '.join(sorted(s.places)[:4])}) "
                         f"nor the off-library offlib_torque_pulse")
        values = {args.effect: args.value}
        truth = s.truth_netlist(values, "lambda_check")
        clean = s.truth_data(Circuit.from_file(truth), values)
        with tempfile.TemporaryDirectory() as tmp:
            work = Path(tmp)
            mc.write_data(s, clean, work / "data.csv")
            mc.write_experiment(s, work / "data.csv", work / "experiment.yaml")
            spec = yaml.safe_load((work / "experiment.yaml").read_text())
            spec["trace"] = {"rounds": 1, "only": [args.effect.split("@")[0]] if not off_library else None}
            (work / "experiment.yaml").write_text(yaml.safe_dump(spec))
            cal = calibrate(work / "experiment.yaml", work / "calibration", with_heldout=False)
        truth.unlink()
        print(f"{args.effect} = {args.value:g}, command {'recorded (latent trace)' if recorded else 'by its levels'}: "
              f"lambda = {s.lam(clean, recorded):.1f} (the bench's sizing; the tool's first fit: "
              f"{cal.initial.fit.chi2:.1f}); accepted {[a[0] for a in cal.accepted] or 'nothing'}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
