"""What the held-out criterion costs the right model: the held-out RMSE ratio of a steady Monte Carlo row
expected from estimating the parameters alone, beside what the row's seeds got.

The Monte Carlo's held-out criterion compares the calibrated model's held-out RMSE with the truth model's
*with its true parameters*, both predicting each left-out crack setting from its measured inputs. A model
of the right structure still estimates its parameters from the other settings, and that error reaches the
prediction. Linearised about the truth (x the parameters and latent inputs, r = (prediction - measured) /
sigma on every row, J = dr/dx, the noise nu ~ N(0, I) on every row, so r(truth) = -nu):

    fold f fitted without its rows:   dx_f = pinv(J_train) nu_train       (the global parameters' error)
    held-out output row i of fold f:  r_i = -nu_i + J_iu sigma_u nu_u(i) + J_ig dx_f,g
    the truth with true parameters:   r_i^ref = -nu_i + J_iu sigma_u nu_u(i)
    ratio = sqrt(sum r_i^2 / sum (r_i^ref)^2)   over the held-out output rows of all folds

(J_iu: row i's sensitivity to its own point's latent input, set to the measured value; sigma_u that input's
noise.) Drawing nu gives the distribution of the ratio that a model of the truth's own structure reaches
when nothing is wrong with it but its estimated parameters, nonlinearity aside: what the right model
itself gets, seed by seed (the column scaling below only keeps pinv's cutoff from dropping the parameters
that are small in SI). The model is the declared one with the case's planted effects freed beside the declared free
parameters (the final model of a seed that found them), at the planted values of the case's records.

    python bench/heldout_expected.py                      # the relief rig's rows (21 points)
    python bench/heldout_expected.py --flows 20           # the 60-point rows
    python bench/heldout_expected.py --mcv                # the MCV rig's rows
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import calibrate_mc as mc  # noqa: E402

LIMIT = 1.1  # the issue's: held-out RMSE <= 1.1 x the truth model's with its true parameters
DRAWS = 20000


def right_model(s: mc.Setup, values: dict[str, float], work: Path):
    """The declared experiment on the noise-free truth, the planted effects in its netlist and free beside the
    declared parameters; returned with x at the truth (its declared values, the planted values, the true
    inputs as the latent inputs)."""
    from blocks.calibrate.data import load_data
    from blocks.calibrate.exchange import free_of
    from blocks.calibrate.experiment import load_experiment
    from blocks.calibrate.model import Model
    from blocks.calibrate.run import latent_globals
    from blocks.circuit import Circuit

    truth_file = s.truth_netlist(values, "heldout_expected")
    clean = s.truth_data(Circuit.from_file(truth_file), values)
    mc.write_data(s, clean, work / "data.csv")
    mc.write_experiment(s, work / "data.csv", work / "experiment.yaml")
    exp = load_experiment(work / "experiment.yaml")
    data = load_data(exp)
    planted = [free_of(s.places[key], value) for key, value in values.items()]
    model = Model(Circuit.from_file(truth_file), exp, data, list(exp.free) + latent_globals(exp, data) + planted)
    x = model.initial()
    for k, g in enumerate(model.layout.globals):
        if g.kind == "declared":
            x[k] = s.values[g.name]
    truth_file.unlink()
    return model, exp, x, clean


def seed_noise(s: mc.Setup, model, clean: dict, seed: int) -> np.ndarray:
    """The normalised noise of every row of ``model`` in the Monte Carlo's seed ``seed`` (drawn as
    ``calibrate_mc.run_seed`` draws it, channel by channel in the truth's order)."""
    rng = np.random.default_rng(seed)
    drawn = {name: rng.normal(size=values.shape) for name, values in clean.items()}
    names = [ch.name for ch in model.channels]
    return np.array([drawn[names[c]][p] for c, p in zip(model.row_channel, model.row_point)])


def ratios(model, exp, x: np.ndarray, nu: np.ndarray) -> tuple[np.ndarray, float]:
    """The held-out RMSE ratios of the linearised right model (module docstring), one per row of the noise
    ``nu`` (draws x the model's rows, normalised), and the chi^2 of the model at x against the noise-free
    data (about 0 when x is the truth)."""
    from blocks.calibrate.heldout import make_folds

    r0 = model.residuals(x)
    everything = np.arange(model.layout.size)
    J = model.jacobian(x, everything, None, r0)
    G = model.layout.n_globals
    outputs = model.output_rows()
    _scheme, folds = make_folds(model, exp.spec.heldout)
    draws = nu.shape[0]
    err = np.zeros(draws)
    ref = np.zeros(draws)
    for _name, idx in folds:
        fold_rows = model.rows_of_points(idx)
        held_latent = [model.layout.latent_index(int(k), i) for k in idx for i in range(len(model.layout.inputs))]
        active = np.setdiff1d(everything, held_latent)
        train = ~fold_rows
        Jt = J[np.ix_(train, active)]
        norms = np.linalg.norm(Jt, axis=0)  # columns scaled: in SI their sizes differ by 1e20, past pinv's cutoff
        norms = np.where(norms > 0, norms, 1.0)
        dx = (np.linalg.pinv(Jt / norms) @ nu[:, train].T) / norms[:, None]  # (active, draws)
        dg = dx[active < G]  # the global parameters' error
        sel = fold_rows & outputs
        # the held-out point's latent input is its measured value, truth + sigma_u * nu of its input row; that
        # row's residual is (latent - measured) / sigma_u, so its own derivative is 1 / sigma_u
        latent_effect = np.zeros((draws, int(sel.sum())))
        for j in held_latent:
            own = np.nonzero((J[:, j] != 0.0) & ~outputs)[0][0]
            latent_effect += np.outer(nu[:, own], J[sel, j] / J[own, j])
        base = -nu[:, sel] + latent_effect
        ref += np.sum(base ** 2, axis=1)
        err += np.sum((base + (J[np.ix_(sel, np.arange(G))] @ dg).T) ** 2, axis=1)
    return np.sqrt(err / ref), float(np.sum(r0 ** 2))


def observed(case: str, records: list[dict]) -> tuple[float, float, int]:
    """(median held-out ratio, share <= LIMIT, seeds) of a case's records."""
    got = [r["heldout_ratio"] for r in records if r["case"] == case and r.get("heldout_ratio") is not None]
    return float(np.median(got)), float(np.mean(np.array(got) <= LIMIT)), len(got)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--flows", type=int, default=None, help="flows per setting (the 60-point rows: 20)")
    parser.add_argument("--mcv", action="store_true", help="the MCV rig's rows")
    parser.add_argument("--draws", type=int, default=DRAWS)
    args = parser.parse_args(argv)
    mc.configure(args.flows)
    kind = "mcv" if args.mcv else "steady"
    path = mc.results_file(kind)
    if not path.exists():
        print(f"error: {path}: no Monte Carlo records to compare with (run bench/calibrate_mc.py first)",
              file=sys.stderr)
        return 2
    records = mc._records(path)
    s = mc.setup(kind)
    rng = np.random.default_rng(0)
    print(f"{path.name}: held-out RMSE ratio of the right model, its parameters estimated (linearised, "
          f"{args.draws} draws) | the row's seeds")
    rows = []
    for case in mc.CASES:
        if case.kind != kind or case.expect not in ("found", "none"):
            continue
        mine = [r for r in records if r["case"] == case.name and "error" not in r]
        if not mine:
            continue
        values = {p.key: mine[0]["planted"][p.key] for p in case.plants}
        with tempfile.TemporaryDirectory() as tmp:
            model, exp, x, clean = right_model(s, values, Path(tmp))
        got, chi2 = ratios(model, exp, x, rng.standard_normal((args.draws, model.n_rows)))
        seeds = sorted(r["seed"] for r in mine if r.get("heldout_ratio") is not None)
        linear, _ = ratios(model, exp, x, np.array([seed_noise(s, model, clean, k) for k in seeds]))
        recorded = np.array([next(r["heldout_ratio"] for r in mine if r["seed"] == k) for k in seeds])
        median, share, n = observed(case.name, mine)
        rows.append({"case": case.name, "planted": values, "expected_median": float(np.median(got)),
                     "expected_share": float(np.mean(got <= LIMIT)), "observed_median": median,
                     "observed_share": share, "seeds": n, "chi2_at_truth": chi2,
                     "per_seed": [{"seed": k, "linear": float(a), "recorded": float(b)}
                                  for k, a, b in zip(seeds, linear, recorded)]})
        print(f"{case.name:28s} expected: median {np.median(got):.3f}, <= {LIMIT} in {np.mean(got <= LIMIT):5.1%}"
              f" | its seeds' noise: median {np.median(linear):.3f}, <= {LIMIT} in {np.mean(linear <= LIMIT):5.1%}"
              f" | recorded: median {median:.3f}, <= {LIMIT} in {share:5.1%} ({n})   [chi^2 at the truth {chi2:.2g}]",
              flush=True)
    target = mc.RECORDS / f"heldout_expected_{path.stem}.json"
    from blocks.result import atomic_write_text

    atomic_write_text(target, json.dumps(rows, indent=1))
    print(f"written {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
