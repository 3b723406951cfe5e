"""Monte Carlo benchmark of ``vphs calibrate``: planted effects, found or not (a benchmark, not in CI).

Truth = the declared netlist + one planted effect (or two, none, or one that is not in the candidate
library) + Gaussian noise on every measured channel, the imposed inputs included. Two experiments:

- steady points: the relief-valve rig (netlists/experiments/relief_rig_steady.yaml: 3 crack settings x 7
  flows; imposed flow Q, compared p1, p2, p3; free k_s, A_ret, R_meter);
- a time series: the open-loop drive line (netlists/experiments/drive_line_series.yaml: a command with
  steps, ramps, a stop and a reversal; compared speed, pA, pB; free m_load, valve.A_max; latent command).

Each planted effect is sized by its non-centrality lambda: the chi^2 of the declared model, fitted to the
noise-free truth, against it (what the declared parameters cannot absorb). lambda is ~ phi^2, so phi is
scaled to the target and checked twice. With ``--recorded`` the declared model's command is the latent
trace of the recording, whose knots absorb part of some effects; lambda is then the one with the recording.
A case's records must all be of one size: a rerun that sizes a case otherwise than its records stops with
an error. Per case and seed the data are drawn, ``calibrate`` runs (with
held-out errors), and these are recorded:

- right: the planted effect is accepted in round 1 as the best by BIC, or it is in the reported ambiguity
  set of the accepted one (indistinguishable places, e.g. either side of a two-port valve);
- recovered: the final estimate of the planted parameter lies within 3 SE of the truth, judged where the
  planted place itself was accepted (in any round);
- chi2/nu after insertion in [0.8, 1.25]; held-out RMSE (normalised, pooled over the output channels) <= 1.1 x
  the truth model's with its true parameters, predicting from the same information (the measured inputs of
  the held-out steady points; the command levels of the time series);
- any effect accepted at all (the false discoveries when nothing or an effect of lambda <= 3 is planted);
- "unexplained discrepancy remains" (the off-library effect).

    python bench/calibrate_mc.py --seeds 20 --workers 2          # every case, results appended as they end
    python bench/calibrate_mc.py --cases steady_flow_force --seeds 3
    python bench/calibrate_mc.py --recorded --cases time_none time_coulomb --seeds 20
                                              # the time series, its command imposed as the recording
    python bench/calibrate_mc.py --table                         # the table from what has run so far
    python bench/calibrate_mc.py --examples                      # rewrite the two example data files

Results go to bench/records/results.jsonl (one line per case and seed; a rerun skips what is there;
committed, since the table is written from them and a new checkout has no out/) and the table to
docs/calibration-montecarlo.md. The truth netlists and each seed's run stay under out/calibrate_mc/.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

EXPERIMENTS = ROOT / "netlists" / "experiments"
STEADY_EXP = EXPERIMENTS / "relief_rig_steady.yaml"
MCV_EXP = EXPERIMENTS / "mcv_vf250_multistep.yaml"
MCV_DATA = ROOT.parent / "shared" / "data" / "mcv_vf250_multistep.csv"
MCV_KP = 895e5  # the truth's spring stiffness kp = kp1 (kp2 = 0 in the experiment): the thesis's 895 bar/unit
TIME_EXP = EXPERIMENTS / "drive_line_series.yaml"
OUT = ROOT / "out" / "calibrate_mc"  # scratch: truth netlists, each seed's run
RECORDS = ROOT / "bench" / "records"  # committed: the per-seed records the table is written from
RESULTS = RECORDS / "results.jsonl"
MCV_RESULTS = RECORDS / "results_mcv.jsonl"  # the steady cases on the MCV rig
TABLE = ROOT / "docs" / "calibration-montecarlo.md"
MIN_SEEDS = 20  # the "at least 20 seeds per case": a row with fewer is shown, not judged
FIT = "restarts"  # session 13: refits near the best tried from more starts; "scaled" (session 12): the fit's
SCALED = ("scaled", "restarts")  # variables scaled to their own sizes; records with neither are older

STEADY_FLOWS_DEFAULT = (12.5, 25.0, 37.5, 50.0, 62.5, 75.0, 87.5)  # l/min, per setting
STEADY_FLOWS = STEADY_FLOWS_DEFAULT
RECORDED = False  # --recorded: the time series's command imposed as its recording, a latent trace
STEADY_SETTINGS = {"1": 30e5, "2": 45e5, "3": 60e5}  # crack setting p_set [Pa] per group
TRIAL = {  # a first guess of each planted parameter (SI); scaled to the target lambda
    "flow_force": 0.1, "line_loss_turbulent": 2e11, "line_loss_laminar": 3e8, "leakage": 1e-11,
    "spool_friction": 2e5, "sensor_offset": 1e4, "sensor_gain": 0.01, "coulomb_friction": 1.0,
    "viscous_friction": 0.005, "stribeck_friction": 2.0, "extra_volume": 5e-4, "transport_delay": 0.01,
    "offlib_curvature": 1e4, "offlib_torque_pulse": 5.0,
}


@dataclass
class Plant:
    key: str  # a candidate place key, or "offlib_*"
    lam: float


@dataclass
class Case:
    name: str
    kind: str  # steady (the relief rig) / mcv (steady, the MCV rig) / time
    plants: list[Plant] = field(default_factory=list)
    expect: str = "found"  # found / none / nothing_claimed / unexplained


CASES = [
    Case("steady_none", "steady", [], "none"),
    Case("steady_flow_force", "steady", [Plant("flow_force@relief", 100)]),
    Case("steady_line_loss_turbulent", "steady", [Plant("line_loss_turbulent@meter.b", 100)]),
    Case("steady_line_loss_laminar", "steady", [Plant("line_loss_laminar@ret.a", 100)]),
    Case("steady_leakage", "steady", [Plant("leakage@R-V", 100)]),
    Case("steady_spool_friction", "steady", [Plant("spool_friction@relief", 100)]),
    Case("steady_sensor_offset", "steady", [Plant("sensor_offset@p1", 100)]),
    Case("steady_sensor_gain", "steady", [Plant("sensor_gain@p3", 100)]),
    Case("steady_two", "steady", [Plant("flow_force@relief", 100), Plant("sensor_offset@p1", 100)]),
    Case("steady_small", "steady", [Plant("flow_force@relief", 3)], "nothing_claimed"),
    Case("steady_off_library", "steady", [Plant("offlib_curvature", 100)], "unexplained"),
    Case("mcv_none", "mcv", [], "none"),
    Case("mcv_flow_force", "mcv", [Plant("flow_force@mcv", 100)]),
    Case("mcv_line_loss_turbulent", "mcv", [Plant("line_loss_turbulent@mcv.C1", 100)]),
    Case("mcv_line_loss_laminar", "mcv", [Plant("line_loss_laminar@meter.b", 100)]),
    Case("mcv_leakage", "mcv", [Plant("leakage@PC-V2", 100)]),
    Case("mcv_sensor_offset", "mcv", [Plant("sensor_offset@p1", 100)]),
    Case("mcv_sensor_gain", "mcv", [Plant("sensor_gain@p3", 100)]),
    Case("mcv_two", "mcv", [Plant("flow_force@mcv", 100), Plant("sensor_offset@p1", 100)]),
    Case("mcv_small", "mcv", [Plant("flow_force@mcv", 3)], "nothing_claimed"),
    Case("mcv_off_library", "mcv", [Plant("offlib_curvature", 100)], "unexplained"),
    Case("time_none", "time", [], "none"),
    Case("time_coulomb", "time", [Plant("coulomb_friction@shaft", 100)]),
    Case("time_viscous", "time", [Plant("viscous_friction@shaft", 100)]),
    Case("time_stribeck", "time", [Plant("stribeck_friction@shaft", 100)]),
    Case("time_leakage", "time", [Plant("leakage@A-B", 100)]),
    Case("time_line_loss_turbulent", "time", [Plant("line_loss_turbulent@motors.a", 100)]),
    Case("time_line_loss_laminar", "time", [Plant("line_loss_laminar@valve.B", 100)]),
    Case("time_extra_volume", "time", [Plant("extra_volume@A", 100)]),
    Case("time_delay", "time", [Plant("transport_delay@u", 100)]),
    Case("time_sensor_offset", "time", [Plant("sensor_offset@pA", 100)]),
    Case("time_sensor_gain", "time", [Plant("sensor_gain@speed", 100)]),
    Case("time_two", "time", [Plant("coulomb_friction@shaft", 100), Plant("transport_delay@u", 100)]),
    Case("time_small", "time", [Plant("coulomb_friction@shaft", 3)], "nothing_claimed"),
    Case("time_off_library", "time", [Plant("offlib_torque_pulse", 100)], "unexplained"),
]


# ---- truth ------------------------------------------------------------------------------------------------
class Setup:
    """The template experiment, its declared circuit and the places of the candidate library."""

    def __init__(self, kind: str):
        from blocks.calibrate.candidates import registered
        from blocks.calibrate.data import Dataset
        from blocks.calibrate.experiment import load_experiment
        from blocks.calibrate.model import Model
        from blocks.calibrate.patch import NetlistDoc
        from blocks.calibrate.run import Stage, context, latent_globals
        from blocks.circuit import Circuit

        self.kind = kind
        self.template = {"steady": STEADY_EXP, "mcv": MCV_EXP, "time": TIME_EXP}[kind]
        self.exp = load_experiment(self.template)
        self.circuit = Circuit.from_file(self.exp.netlist)
        self.doc = NetlistDoc.read(self.exp.netlist)
        # the truth's parameters: the netlist's values with the experiment's overrides (the MCV rig: no flow
        # force, kp2 = 0) and, on the MCV rig, the thesis's stiffness
        self.truth_parameters = dict(self.exp.overrides, **({"mcv.kp1": MCV_KP} if kind == "mcv" else {}))
        self.values = self.circuit.vectors(self.truth_parameters).values
        self.sigma = {ch.name: ch.noise for ch in self.exp.channels}
        self.steady_inputs = {c.name: c.parameter for c in self.exp.inputs if c.parameter is not None}
        self.outputs = [c.name for c in self.exp.outputs]
        if kind == "steady":
            labels, q = [], []
            for label in STEADY_SETTINGS:
                for flow in STEADY_FLOWS:
                    labels.append(label)
                    q.append(flow / 60000.0)
            self.labels, self.inputs = labels, {"Q": np.array(q)}
            self.t = None
        elif kind == "mcv":  # the true inputs: the 21 points of the thesis's measurement (Q and p2)
            from blocks.datafile import read_table

            table = read_table(MCV_DATA, group="setting")
            self.labels = list(table.labels)
            self.inputs = {"Q": np.array(table.columns["Q"]), "p2": np.array(table.columns["p2"])}
            self.t = None
        else:
            r = self.circuit.simulate()
            self.t = r.t.copy()
            self.labels = ["all"] * len(self.t)
            self.inputs = {}
        self.Dataset, self.Model = Dataset, Model
        clean = self.truth_data(self.circuit, {})
        data = self.dataset(clean)
        for ch in self.exp.channels:  # channel units as the data file would give them
            ch.unit = {"Q": "l/min", "cmd": "1", "speed": "rpm"}.get(ch.name, "bar")
            if not ch.si_unit or ch.si_unit == "SI":
                ch.si_unit = "m^3*s^-1" if ch.name == "Q" else "1"
        globals_ = list(self.exp.free) + latent_globals(self.exp, data)
        model = Model(self.circuit, self.exp, data, globals_)
        stage = Stage(self.exp.netlist, model, None, None)
        self.ctx = context(stage, self.exp, data, self.doc)
        self.places = {}
        for cand in registered().values():
            for place in cand.places(self.ctx):
                self.places[place.key] = place
        self.registered = registered()

    def dataset(self, measured: dict):
        n = len(self.labels)
        return self.Dataset("time" if self.kind == "time" else "steady", n, self.t, list(self.labels), dict(measured), dict(self.sigma), None,
                            {k: "given" for k in self.sigma})

    def truth_netlist(self, plants: dict[str, float], tag: str) -> Path:
        """The declared netlist with the planted netlist effects at their values (a file per case)."""
        doc = self.doc.copy()
        for key, value in plants.items():
            if key.startswith("offlib_torque_pulse"):
                doc.add_parameter("mc_pulse", float(value))
                doc.add_component("mc_pulse_profile", "profile", {
                    "times": [0, 0.9, 0.95, 1.25, 1.3], "values": [0, 0, "mc_pulse", "mc_pulse", 0]})
                doc.add_component("mc_pulse_torque", "torque_source", {})
                doc.section("nets")["mc_pulse_net"] = ["mc_pulse_profile.y", "mc_pulse_torque.tau"]
                doc.set_net_ports("shaft", doc.net_ports("shaft") + ["mc_pulse_torque.port"])
                continue
            if key.startswith("offlib_"):
                continue
            place = self.places[key]
            if place.kind != "netlist":
                continue
            doc.add_parameter(place.param, float(value))
            self.registered[place.candidate].patch(doc, place)
        path = OUT / "truth" / f"{self.kind}_{tag}{_variant()}.yaml"
        return doc.write(path, header=f"Monte Carlo truth: {tag}")

    def truth_data(self, circuit, plants: dict[str, float], inputs: dict | None = None) -> dict:
        """Noise-free measured channels of the truth (steady inputs at their true values, or ``inputs``), SI."""
        out = {}
        if self.kind != "time":
            inputs = self.inputs if inputs is None else inputs
            out = {name: np.array(values, dtype=float) for name, values in inputs.items()}
            rows = [self.steady_truth(circuit, k, {self.steady_inputs[name]: float(values[k])
                                                   for name, values in inputs.items()})
                    for k in range(len(self.labels))]
            for name in self.outputs:
                out[name] = np.array([row[name] for row in rows])
        else:
            r = circuit.simulate(self.truth_parameters)
            for ch in self.exp.channels:
                out[ch.name] = np.interp(self.t, r.t, r[ch.signal])
        for key, value in plants.items():
            if key.startswith("sensor_offset@"):
                out[key.split("@")[1]] = out[key.split("@")[1]] + value
            elif key.startswith("sensor_gain@"):
                out[key.split("@")[1]] = out[key.split("@")[1]] * (1.0 + value)
            elif key == "offlib_curvature":  # a sensor with a curved characteristic on p3
                p3 = out["p3"]
                center, width = (55e5, 25e5) if self.kind == "mcv" else (50e5, 30e5)  # the points' p3 range
                out["p3"] = p3 + value * ((p3 - center) / width) ** 2
        return out

    def steady_truth(self, circuit, k: int, inputs: dict) -> dict:
        """The truth's outputs at steady point k: a settling run of 8 x the netlist's t_end (the relief rig:
        a planted leakage fills the inlet volume with a time constant of about 0.1 s at low flow, still
        moving at 0.15 s), then, where the circuit has an isolated stable equilibrium near the run's end,
        that equilibrium (both rigs; not the relief rig with a planted spool friction, whose spool sticks
        anywhere in a band)."""
        over = dict(self.truth_parameters)
        over.update(self.exp.groups.get(self.labels[k], {}))
        if self.kind == "steady":
            over["p_set"] = STEADY_SETTINGS[self.labels[k]]
        over.update(inputs)
        t_end = 8.0 * circuit.settings.t_end if self.kind == "steady" else 2.0
        r = circuit.simulate(over, settings=circuit.settings.with_(t_end=t_end, dt_out=t_end / 10.0))
        values = {name: r[self._signal(name)][-1] for name in self.outputs}
        eq = circuit.equilibrium(over, guess=r.states[-1], t=t_end)
        if eq.stable:
            values = {name: eq[self._signal(name)] for name in self.outputs}
        return values

    def _signal(self, channel: str) -> str:
        return next(c.signal for c in self.exp.channels if c.name == channel)

    def lam(self, clean: dict, recorded: bool = False) -> float:
        """chi^2 of the declared model fitted to the noise-free truth. ``recorded`` (the time series): the
        experiment of ``--recorded``, its command a latent trace whose knots are chosen from the noise-free
        recording and fitted with the parameters, so that lambda is what the declared model with its knots
        cannot absorb."""
        from blocks.calibrate.run import latent_globals

        if recorded:
            return self._lam_recorded(clean)
        data = self.dataset(clean)
        globals_ = list(self.exp.free) + latent_globals(self.exp, data)
        model = self.Model(self.circuit, self.exp, data, globals_)
        return self._fit_from_truth(model)

    def _lam_recorded(self, clean: dict) -> float:
        import tempfile

        from blocks.calibrate.data import load_data
        from blocks.calibrate.experiment import load_experiment
        from blocks.calibrate.run import latent_globals
        from blocks.circuit import Circuit

        with tempfile.TemporaryDirectory() as tmp:
            work = Path(tmp)
            write_data(self, clean, work / "data.csv")
            write_experiment(self, work / "data.csv", work / "experiment.yaml", recorded=True)
            exp = load_experiment(work / "experiment.yaml")
            data = load_data(exp)
            globals_ = list(exp.free) + latent_globals(exp, data)
            model = self.Model(Circuit.from_file(exp.netlist), exp, data, globals_)
            return self._fit_from_truth(model, also_from_initial=True)

    def _fit_from_truth(self, model, also_from_initial: bool = False) -> float:
        """chi^2 of ``model`` fitted from the truth's declared values; ``also_from_initial``: the lower of
        that and the fit from the experiment's own start (the tool's), for a fit with several minima (the
        knot times of a latent trace: on the drive line the two starts differ by up to 4 % in chi^2)."""
        from blocks.calibrate.fit import fit

        initial = model.initial()
        x0 = initial.copy()
        for k, g in enumerate(model.layout.globals):  # start at the truth's values
            if g.kind == "declared":
                x0[k] = self.values[g.name]
        starts = [x0, initial] if also_from_initial else [x0]
        return min(fit(model, x, np.ones(model.layout.size, dtype=bool), max_nfev=60).chi2 for x in starts)

    def size(self, case: Case) -> tuple[dict[str, float], dict[str, float], dict[str, float]]:
        """Each planted effect scaled to its target lambda (alone); returns the values, the lambdas reached
        and the lambdas with the command given by its levels. Under ``--recorded`` the lambda is the one
        with the recording (:meth:`lam`, ``recorded``), refined from the size by the levels: the knots of
        the latent trace absorb part of some effects (the off-library torque pulse more than half)."""
        values, lams, by_levels = {}, {}, {}
        for plant in case.plants:
            phi, lam = self._scale(plant, TRIAL[plant.key.split("@")[0]], recorded=False)
            by_levels[plant.key] = lam
            if self.kind == "time" and RECORDED:
                phi, lam = self._scale(plant, phi, recorded=True)
            values[plant.key], lams[plant.key] = phi, lam
        return values, lams, by_levels

    def _scale(self, plant: Plant, phi: float, recorded: bool) -> tuple[float, float]:
        """``phi`` scaled until the plant's lambda is at its target: for "lambda >= 100" at or just above
        it, for "lambda <= 3" at or just below (at most 5 evaluations)."""
        from blocks.circuit import Circuit

        lam = None
        big = plant.lam >= 100
        for _ in range(5):
            plants = {plant.key: phi}
            circuit = Circuit.from_file(self.truth_netlist(plants, f"size_{plant.key}"))
            lam = self.lam(self.truth_data(circuit, plants), recorded)
            if lam <= 0:
                phi *= 10
                continue
            ratio = plant.lam / lam
            if (big and 0.87 <= ratio <= 1.0) or (not big and 1.0 <= ratio <= 1.15):
                break
            phi *= float(np.sqrt(ratio)) * ((1.03 if big else 0.97) if abs(ratio - 1) < 0.2 else 1.0)
        return phi, lam


# ---- one seed ---------------------------------------------------------------------------------------------
_SETUPS: dict[str, Setup] = {}
_SIZES: dict[str, tuple] = {}


def setup(kind: str) -> Setup:
    if kind not in _SETUPS:
        _SETUPS[kind] = Setup(kind)
    return _SETUPS[kind]


def write_data(s: Setup, measured: dict, path: Path) -> None:
    from blocks.result import atomic_write_text

    if s.kind != "time":
        lines = ["# Monte Carlo data (synthetic)", "setting,Q [l/min],p1 [bar],p2 [bar],p3 [bar]"]
        for k, label in enumerate(s.labels):
            lines.append(f"{label},{measured['Q'][k] * 60000:.6f},{measured['p1'][k] / 1e5:.6f},"
                         f"{measured['p2'][k] / 1e5:.6f},{measured['p3'][k] / 1e5:.6f}")
    else:
        lines = ["# Monte Carlo data (synthetic)", "t [s],cmd [1],speed [rpm],pA [bar],pB [bar]"]
        rpm = 2 * np.pi / 60
        for k, t in enumerate(s.t):
            lines.append(f"{t:.6f},{measured['cmd'][k]:.7f},{measured['speed'][k] / rpm:.5f},"
                         f"{measured['pA'][k] / 1e5:.6f},{measured['pB'][k] / 1e5:.6f}")
    atomic_write_text(path, "\n".join(lines) + "\n")


def write_experiment(s: Setup, data_path: Path, path: Path, recorded: bool | None = None) -> None:
    from blocks.result import atomic_write_text

    spec = dict(s.exp.located.data)
    spec["netlist"] = str(s.exp.netlist)
    spec["data"] = str(data_path)
    spec["description"] = "Monte Carlo seed"
    if "group_table" in spec:
        table = dict(spec["group_table"])
        table["file"] = str((s.template.parent / table["file"]).resolve())
        spec["group_table"] = table
    if s.kind == "mcv":  # the real data's experiment refits 8 candidates per round; the Monte Carlo the default 3
        spec["trace"] = {"rounds": 3, "top": 3}
    if s.kind == "time" and (RECORDED if recorded is None else recorded):  # the profile reads the recording
        netlist = yaml.safe_load(Path(s.exp.netlist).read_text())
        netlist["components"]["cmd"]["params"] = {"times": {"csv": str(data_path), "column": "t"},
                                                  "values": {"csv": str(data_path), "column": "cmd"}}
        atomic_write_text(path.parent / "recorded.yaml", yaml.safe_dump(netlist, sort_keys=False))
        spec["netlist"] = str(path.parent / "recorded.yaml")
        spec["inputs"] = {"cmd": dict(spec["inputs"]["cmd"], latent="trace")}
    atomic_write_text(path, yaml.safe_dump(spec, sort_keys=False))


def run_seed(case: Case, seed: int, sizes: tuple) -> dict:
    from blocks.calibrate.run import calibrate
    from blocks.circuit import Circuit
    from blocks.provenance import environment

    s = setup(case.kind)
    values, lams, by_levels = sizes
    truth_file = s.truth_netlist(values, case.name)
    clean = s.truth_data(Circuit.from_file(truth_file), values)
    rng = np.random.default_rng(seed)
    noisy = {k: v + rng.normal(size=v.shape) * s.sigma[k] for k, v in clean.items()}
    work = OUT / "runs" / (case.name + _variant()) / f"seed{seed}"
    write_data(s, noisy, work / "data.csv")
    write_experiment(s, work / "data.csv", work / "experiment.yaml")
    started = time.perf_counter()
    cal = calibrate(work / "experiment.yaml", work / "calibration")
    seconds = time.perf_counter() - started
    outputs = [c.name for c in s.exp.outputs]
    # the truth model's held-out error: true parameters, predicting from what a held-out prediction has (the
    # measured steady inputs; for the time series the command levels, which the input channel pins down)
    reference = clean if s.kind == "time" else s.truth_data(Circuit.from_file(truth_file), values,
                                                            {name: noisy[name] for name in s.inputs})
    if s.kind == "time" and RECORDED:  # what the recording tells of the command: the spline it alone gives
        reference = s.truth_data(Circuit.from_file(command_from_recording(truth_file, s.t, noisy["cmd"],
                                                                          s.sigma["cmd"], work)), values)
    truth_err = float(np.mean(np.concatenate([((noisy[o] - reference[o]) / s.sigma[o]) ** 2 for o in outputs])))
    accepted = [a[0] for a in cal.accepted]
    first = cal.rounds[0].decision if cal.rounds else None
    rounds = [{"accepted": r.decision.accepted.score.place.key if r.decision.accepted else None,
               "ambiguous": r.decision.ambiguous,
               "best_by_bic": r.decision.refits[0].score.place.key if r.decision.refits else None,
               # every refit's dBIC, and from its first start alone where it was tried from more
               "refits": [{"key": rf.score.place.key, "dbic": rf.dbic,
                           "dbic_first_start": rf.starts[0][1] - rf.base_chi2 + np.log(rf.fit.n),
                           "starts": len(rf.starts)} for rf in r.decision.refits],
               "top_score": max((sc.place.key for sc in r.scores if sc.status == "screened"),
                                key=lambda k: next(sc.T for sc in r.scores if sc.place.key == k), default=None),
               # why a planted effect that was refitted was not accepted (its tests, held-out included)
               "planted_refits": [{"key": rf.score.place.key, "dbic": rf.dbic, "z": rf.z,
                                   "heldout": rf.heldout.error if rf.heldout else None,
                                   "base_heldout": r.decision.base_heldout.error if r.decision.base_heldout
                                   else None,
                                   "heldout_score": rf.heldout.score if rf.heldout else None,
                                   "base_heldout_score": r.decision.base_heldout.score if r.decision.base_heldout
                                   else None, "reasons": list(rf.reasons)}
                                  for rf in r.decision.refits if rf.score.place.key in [p.key for p in case.plants]]}
              for r in cal.rounds]
    # recovery is judged on the planted place's own parameter in the final fit, whichever round accepted it;
    # an ambiguous alternative that was accepted instead estimates a parameter of other meaning (a leakage
    # P1->T is not a leakage R->V of the same conductance), so it is not compared with the planted value
    final = {key: (value, se) for key, _title, _where, _param, value, se, _unit in cal.accepted}
    exchanges = [{"out": ex.out_key, "in": ex.in_key, "dbic": ex.dbic, "made": ex.made} for ex in cal.exchanges]
    removals = [{"effect": t.key, "dbic": t.dbic, "z": t.z, "refitted": t.refitted, "removed": t.removed}
                for t in cal.removals]
    found, recovered = [], []
    for plant in case.plants:  # in the final model, or ambiguous with an effect that is
        found.append(plant.key in final
                     or any(plant.key in r["ambiguous"] for r in rounds if r["accepted"] in final)
                     or any(e["made"] and e["out"] == plant.key and e["dbic"] > -10 for e in exchanges))
        if plant.key in final:
            est, se = final[plant.key]
            recovered.append(bool(abs(est - values[plant.key]) <= 3 * se))
        else:
            recovered.append(None)
    first_right = bool(case.plants) and first is not None and first.accepted is not None and (
        first.accepted.score.place.key in [p.key for p in case.plants]
        or any(p.key in first.ambiguous for p in case.plants))
    ranked_first = first is not None and bool(first.refits) and first.accepted is first.refits[0]
    ho_ratio = float(np.sqrt(cal.final.heldout.error / truth_err)) if cal.final and cal.final.heldout else None
    true_command_err = float(np.mean(np.concatenate([((noisy[o] - clean[o]) / s.sigma[o]) ** 2 for o in outputs])))
    return {"case": case.name, "seed": seed, "kind": case.kind, "expect": case.expect, "fit": FIT,
            "planted": {p.key: values.get(p.key) for p in case.plants}, "lambda": lams,
            "lambda_levels": by_levels,
            "accepted": accepted, "rounds": rounds, "exchanges": exchanges, "removals": removals, "found": found,
            "recovered": recovered,
            "first_right": first_right, "ranked_first": bool(ranked_first),
            "chi2nu_after": cal.final.lof.reduced if cal.final else None,
            "heldout_ratio": ho_ratio, "unexplained": cal.unexplained, "seconds": seconds,
            "heldout_ratio_true_command": (float(np.sqrt(cal.final.heldout.error / true_command_err))
                                           if cal.final and cal.final.heldout and s.kind == "time" else None),
            "estimates": {key: [value, se] for key, (value, se) in final.items()},
            "unsettled": cal.final.fit.unsettled if cal.final else None,
            "lengthened": len(cal.final.model.run_end) if cal.final else None,
            "simulations": cal.simulations, "environment": environment()}


def command_from_recording(truth_file: Path, t: np.ndarray, recorded: np.ndarray, sigma: float, work: Path) -> Path:
    """The truth netlist with its command replaced by the latent trace's spline fitted to the recording alone
    (knots at samples, as :func:`blocks.calibrate.latent_trace.choose_knots` starts them): the truth model
    predicting from the same information as a held-out block of the recorded-command experiment has."""
    from blocks.calibrate.latent_trace import choose_knots, knot_values
    from blocks.result import atomic_write_text

    knots = choose_knots(t, recorded, sigma)
    netlist = yaml.safe_load(truth_file.read_text())
    netlist["components"]["cmd"]["params"] = {"times": [float(v) for v in t[knots]],
                                              "values": [float(v) for v in knot_values(t, recorded, knots)]}
    path = work / "truth_from_recording.yaml"
    atomic_write_text(path, yaml.safe_dump(netlist, sort_keys=False))
    return path


def configure(flows: int | None, recorded: bool = False) -> None:
    """The steady experiment's flows per setting: the 7 of the main table, or ``flows`` evenly spaced from
    12.5 to 87.5 l/min (a denser experiment; its results go to a file of their own). ``recorded``: the time
    series's command imposed as its recording, a latent trace (results in a file of their own)."""
    global STEADY_FLOWS, RESULTS, RECORDED
    new = STEADY_FLOWS_DEFAULT if not flows else tuple(float(q) for q in np.linspace(12.5, 87.5, flows))
    if new != STEADY_FLOWS:
        _SETUPS.pop("steady", None)
        _SIZES.clear()
    STEADY_FLOWS, RECORDED = new, recorded
    RESULTS = RECORDS / ("results_recorded.jsonl" if recorded else "results.jsonl" if not flows
                     else f"results_flows{flows}.jsonl")


def _variant() -> str:
    """The suffix of the files of a denser steady experiment or of the recorded command (their truth netlists
    and runs are their own: two runs of the bench at once must not overwrite each other's)."""
    if RECORDED:
        return "_recorded"
    return "" if STEADY_FLOWS == STEADY_FLOWS_DEFAULT else f"_flows{len(STEADY_FLOWS)}"


def _worker(args) -> dict:
    case_name, seed, sizes, flows, recorded = args
    configure(flows, recorded)
    case = next(c for c in CASES if c.name == case_name)
    try:
        return run_seed(case, seed, sizes)
    except Exception as exc:  # a failure is a result too: counted, never hidden
        return {"case": case_name, "seed": seed, "error": f"{type(exc).__name__}: {exc}"}


# ---- the table --------------------------------------------------------------------------------------------
def results_file(kind: str) -> Path:
    return MCV_RESULTS if kind == "mcv" else RESULTS


def load_results() -> list[dict]:
    out = []
    for path in {RESULTS, MCV_RESULTS}:
        if path.exists():
            out += [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return out


def table(results: list[dict]) -> str:
    lines = ["# Calibration Monte Carlo (bench/calibrate_mc.py)", "",
             "Planted effects, found or not: truth = the declared netlist + the planted effect(s) + Gaussian noise on "
             "every measured channel, inputs included; each effect sized by its non-centrality lambda (chi^2 of the "
             "declared model fitted to the noise-free truth). Steady: the relief rig "
             "(netlists/experiments/relief_rig_steady.yaml, 21 points, sigma 0.5 l/min and 0.2 bar); time series: the "
             "open-loop drive line (netlists/experiments/drive_line_series.yaml, 1701 samples, sigma 0.005, 5 rpm, 1 bar). "
             "`vphs calibrate` with held-out errors (leave one group out; 4 contiguous blocks), at most three traces.",
             "",
             "Columns: **right** = the planted effect in the final model, or in the reported ambiguity set of an "
             "effect in it (each round accepts the best by BIC; with two effects or more, the exchange check after "
             "the trace may swap an early one for an alternative of its round, and the elimination check may take "
             "one out); **rec** = final estimate within 3 "
             "SE of the planted value, judged in the seeds where the planted place itself is in the final model "
             "(an ambiguous alternative "
             "accepted instead, e.g. a leakage P1->T for the planted R->V, estimates a parameter of other meaning "
             "and is not compared); **chi2/nu ok** = final chi^2/nu in "
             "[0.8, 1.25]; **held-out ok** = held-out RMSE (pooled over the outputs) <= 1.1 x that of the truth model "
             "with its true parameters predicting from the same information (measured steady inputs); **claimed** = "
             "any effect accepted; **unexpl** = 'unexplained discrepancy remains'. Seed k draws the same noise in "
             "every case of its kind, so rows are paired.",
             "",
             "The criteria are the issue's, applied per seed and unchanged. Three of them cannot be met in every "
             "seed, whatever the calibration does; the reference rows and the theory show it:",
             "",
             "- chi^2/nu in [0.8, 1.25]: the `*_none` rows fit the true model (declared = truth). With 21 steady "
             "points nu is about 60 and chi^2/nu has a standard deviation of sqrt(2/60) = 0.18: the true model "
             "itself is in the band in " + _band_rate(60) + " of seeds in theory (" + _reference(results, "steady_none",
             "chi") + " here); for the time series (nu about 5000) in " + _band_rate(5000) + ".",
             "- held-out RMSE <= 1.1 x the truth model's with its TRUE parameters: a calibrated model carries the "
             "error of its estimated parameters, which a leave-one-setting-out prediction from 14 points "
             "extrapolates; the truth model with its parameters refitted the same way (`steady_none`) is within "
             "1.1 x in " + _reference(results, "steady_none", "heldout") + " of seeds. One parameter more (the "
             "planted one, itself correlated with the spring stiffness) widens that further: in `steady_flow_force` "
             "the accepted model is the truth's own structure, refitted, so its held-out ratio is what estimating "
             "the parameters costs, not a wrong model. The section at the end repeats the steady cases with 60 "
             "points instead of 21, where both criteria come within reach."
             + _heldout_expected(RECORDS / "results.jsonl", results),
             "- no effect claimed at lambda <= 3: such an effect is real, and the tests accept it whenever the "
             "noise lifts its chi^2 drop over 10 + ln n (dBIC < -10; the 3-SE test is then passed too). For one "
             "candidate that drop is non-central chi^2_1(lambda), so the planted effect passes in "
             + _chance_claim(results, "steady_small", 84) + " on the relief rig and in "
             + _chance_claim(results, "time_small", 6804) + " on the drive line "
             "(before the held-out test, which lowers it, and the other candidates, which raise it).",
             "",
             "Versions. Session 7 found that a held-out fold's refit stopped at 20 evaluations whether or not it "
             "had converged, and a fold cut short predicts worse than the model can: in `steady_leakage` seed 10 "
             "the planted leakage R->V got a held-out error of 4.8 instead of 0.86 and was refused in round 1. Each "
             "fold is now refitted to convergence (`blocks/calibrate/heldout.py`). Session 7 also added the "
             "elimination check after the exchange check (an effect that, beside the others, no longer passes the "
             "tests it was accepted by is taken out). Every steady row (this table's, the 60-point section's and "
             "the MCV rig's) was rerun in session 7 with both, and every time-series row in session 8 (against "
             "their records from sessions 5 to 7, no seed's accepted effects or verdict changed, and no held-out "
             "ratio moved by more than 0.005). Session 5 "
             "brought steady points solved as equilibria (the steady rows' CPU time fell 7-fold), the "
             "residual-structure test in the verdict, the ambiguity set extended to places parallel to a refitted "
             "ambiguous alternative and candidate refits continued once when cut short; session 6 the exchange "
             "check. " + _after_trace_effect()
             + " (The exchange check's margin, a swap must lower BIC by over 1, came after a first run in which "
             "`time_two` swapped the delay on the command for the same delay on the spool, at dBIC -0.0, in 4 "
             "seeds; those 4 seeds were rerun with it.) "
             + " ".join(p for p in (_scaled_fit(), _restarts(), _stuck_refits(), _reruns()) if p),
             ""] + case_rows(results) + [""] + rec_misses(results)
    lines += ["", "Per-seed records: bench/records/results.jsonl. Rerun: "
                  "`python bench/calibrate_mc.py --seeds 20 --workers 2`; table only: `--table`.", ""]
    for dense in sorted(RECORDS.glob("results_flows*.jsonl")):
        flows = int(dense.stem.removeprefix("results_flows"))
        lines += _section(dense, f"The steady cases with {flows} flows per setting ({3 * flows} points)", lambda rows: (
            f"The same relief rig, settings, noise and criteria, with {flows} flows per setting evenly from "
            f"12.5 to 87.5 l/min instead of 7; each effect sized again to lambda of about 100 (so it is "
            f"smaller). chi^2/nu of a right model is then in [0.8, 1.25] in "
            f"{_band_rate(3 * flows * 4 - 3 * flows - 3)} of seeds in theory. At lambda <= 3 the planted "
            f"effect passes dBIC < -10 by its noise in {_chance_claim(rows, 'steady_small', 3 * flows * 4)}."),
            f"`python bench/calibrate_mc.py --flows {flows} --seeds 20 --workers 2` (the steady cases only).")
    lines += _section(RECORDS / "results_recorded.jsonl",
                      "The time series with the command imposed as its recording (a latent trace)", lambda rows: (
        "The same drive line, truths, noise and criteria; but the experiment has no command profile "
        "of its own: the netlist's profile reads the seed's recorded command column (noise 0.005), "
        "and the experiment lists it as `cmd: {signal: cmd, latent: trace}`, so the command is a "
        "linear spline whose knots are chosen from the recording and whose knot times and values "
        "are fitted with the parameters (blocks/calibrate/latent_trace.py). The truth's command steps "
        "between samples (at 0.2 to 0.201 s and 1.6 to 1.601 s; samples every 2 ms): the knots' times "
        "find it. The held-out reference is the truth model predicting from the same information: its "
        "command the spline that the recording alone gives (knots at samples, as the tool starts them; "
        "a held-out block's knots start there too). The median held-out ratio against the truth model "
        "with its true command is " + _median_of(rows, "heldout_ratio_true_command") + ". A seed takes "
        + _span(r["seconds"] for r in rows if "error" not in r) + " s here. " + _recorded_sizes(rows)
        + " A transport delay on the command shorter than a sample interval is another matter: the knots' times "
        "take it whole (`time_delay`'s 0.23 ms: lambda 108 with the levels, 0.1 with the recording: `python "
        "bench/recorded_lambda.py transport_delay@u 0.000227`), so that case is not run here. "
        + _recorded_misses(rows)),
        lambda rows: "`python bench/calibrate_mc.py --recorded --cases " + " ".join(
            c.name for c in CASES if any(r["case"] == c.name for r in rows))
        + " --seeds 20 --workers 2` (the time-series cases only).")
    lines += _section(MCV_RESULTS, "The steady cases on the MCV rig", lambda rows: (
        "The motion-control valve's test rig of the real data (netlists/experiments/mcv_vf250_multistep.yaml: "
        "the chapter-2 VAA valve without flow force, kp free, 21 points at the thesis's three crack "
        "settings; Q and p2 imposed as noisy inputs, sigma 0.5 l/min and 0.3 bar; p1 and p3 compared, 0.3 "
        "bar). The truth: that model with kp = 895 bar/unit at the measured points' Q and p2, plus the "
        "planted effect. Steady points by equilibrium (`steady.method: equilibrium`, Newton from each "
        "point's first settling run), which makes a seed affordable here (a settling run of this rig takes "
        "2 to 40 ms, a Newton solve 0.15 ms: `python bench/steady_points.py`). Three candidates refitted per "
        "round (the default; the real data's experiment refits 8). With 21 points, 4 channels and 2 latent "
        "inputs per point nu = 84 - 43 = "
        f"41: the true model's chi^2/nu is in [0.8, 1.25] in {_band_rate(41)} of seeds in theory. The off-library "
        "effect is a p3 sensor with a curved characteristic, c*((p3 - 55 bar)/25 bar)^2: over the points' "
        "p3 range (31 to 80 bar) a p3 gain and offset, both in the library, take most of it, so the "
        "tool may well 'explain' it as a linear sensor error (the claimed column shows how often); what "
        "they leave is a curve in p3 against its fitted value, which the verdict's structure test (a "
        "cubic in each output's fitted value, Bonferroni with the other tests) reports as an "
        "unexplained discrepancy when it is significant. How much is left: " + _linear_sensor_leftover(rows)
        + " (non-central chi^2), so 'unexplained in >= 90 %' is out of reach for this effect on these "
        "21 points: the library's linear sensor error takes most of it. At lambda <= 3 the planted effect "
        "passes dBIC < -10 by its noise in " + _chance_claim(rows, "mcv_small", 84) + "."),
        "`python bench/calibrate_mc.py --cases mcv_none mcv_flow_force ... --seeds 20 --workers 2` (the MCV "
        "cases run when named).")
    return "\n".join(lines)


def _section(path: Path, heading: str, text, rerun) -> list[str]:
    """A section of the table from one records file (none if it does not exist): its heading, ``text(rows)``,
    the case rows, the misses in the rec column and how to rerun it (``rerun``: the command, or a function of
    the rows that gives it)."""
    if not path.exists():
        return []
    rows = _records(path)
    command = rerun(rows) if callable(rerun) else rerun
    return [f"## {heading}", "", text(rows) + _heldout_expected(path, rows), ""] + case_rows(rows) + [""] \
        + rec_misses(rows) + ["", f"Records: bench/records/{path.name}. Rerun: {command}", ""]


def case_rows(results: list[dict]) -> list[str]:
    """The table of every case that has results: rates over its seeds and the issue's criterion."""
    by_case: dict[str, list[dict]] = {}
    for r in results:
        by_case.setdefault(r["case"], []).append(r)

    def pct(values):
        values = [v for v in values if v is not None]
        return f"{100 * np.mean(values):.0f} % ({sum(values)}/{len(values)})" if values else "-"

    lines = ["| case | planted | lambda | seeds | right | rec | chi2/nu ok | mean chi2/nu | held-out ok | "
             "median held-out ratio | claimed | unexpl | errors | median s | criterion | pass |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for case in CASES:
        rows = by_case.get(case.name, [])
        if not rows:
            continue
        good = [r for r in rows if "error" not in r]
        errors = len(rows) - len(good)
        planted = ", ".join(f"{k} = {v:.3g}" for k, v in (good[0]["planted"] if good else {}).items()) or "none"
        lam = ", ".join(f"{v:.3g}" for v in (good[0]["lambda"] if good else {}).values()) or "-"
        resized = any(r.get("lambda_levels") and r["lambda_levels"] != r["lambda"] for r in results)
        if lam != "-" and resized and not good[0].get("lambda_levels"):
            lam += " (by the levels)"  # a row of a section sized by another lambda, not yet resized
        right = [all(r["found"]) for r in good] if case.plants else []
        rec = [_recovered(case, r) for r in good] if case.plants else []
        chi_ok = [r["chi2nu_after"] is not None and 0.8 <= r["chi2nu_after"] <= 1.25 for r in good]
        ho_ok = [r["heldout_ratio"] is not None and r["heldout_ratio"] <= 1.1 for r in good]
        claimed = [bool(r["accepted"]) for r in good]
        unexpl = [bool(r["unexplained"]) for r in good]
        med = np.median([r["seconds"] for r in good]) if good else float("nan")
        chi_mean = np.mean([r["chi2nu_after"] for r in good if r["chi2nu_after"] is not None]) if good else np.nan
        ho_med = np.median([r["heldout_ratio"] for r in good if r["heldout_ratio"] is not None]) if good else np.nan
        n = len(good)
        if case.expect == "found":
            crit = "right >= 90 %, rec >= 90 %, chi2/nu ok, held-out ok"
            ok = (n > 0 and np.mean(right) >= 0.9 and (np.mean([x for x in rec if x is not None]) >= 0.9
                  if any(x is not None for x in rec) else False) and np.mean(chi_ok) >= 0.9 and np.mean(ho_ok) >= 0.9)
        elif case.expect == "none":
            crit = "claimed <= 5 %"
            ok = n > 0 and np.mean(claimed) <= 0.05
        elif case.expect == "nothing_claimed":
            crit = "claimed = 0 (lambda <= 3)"
            ok = n > 0 and not any(claimed)
        else:
            crit = "unexplained in >= 90 %"
            ok = n > 0 and np.mean(unexpl) >= 0.9
        verdict = ("PASS" if ok else "FAIL") if n >= MIN_SEEDS else f"not judged ({n} < {MIN_SEEDS} seeds)"
        lines.append(f"| {case.name} | {planted} | {lam} | {n} | {pct(right) if case.plants else '-'} | "
                     f"{pct(rec) if case.plants else '-'} | {pct(chi_ok)} | {chi_mean:.3g} | {pct(ho_ok)} | "
                     f"{ho_med:.3g} | {pct(claimed)} | {pct(unexpl)} | {errors} | {med:.0f} | {crit} | "
                     f"{verdict} |")
    return lines


def _recorded_sizes(rows: list[dict]) -> str:
    """How the recorded-command rows are sized: from their size by the command's levels (the first table's, and
    its lambda with the levels) to their size by their lambda with the recording (from the records)."""
    firsts = {c.name: next((r for r in rows if r["case"] == c.name and "error" not in r and r.get("lambda_levels")),
                           None) for c in CASES}
    sized = {case: r for case, r in firsts.items() if r is not None}  # every seed of a case has its sizes
    if not sized:
        return "The rows are sized by the command's levels."
    by_levels = {r["case"]: r["planted"] for r in _records(RECORDS / "results.jsonl") if "error" not in r}

    def resized(case: str, r: dict) -> str:
        parts = []
        for key, value in r["planted"].items():
            first = by_levels.get(case, {}).get(key)
            start = f"{first:.3g}" if first is not None else "its size"
            kept = first is not None and np.isclose(first, value, rtol=1e-9, atol=0.0)
            parts.append(f"`{case}` {start} (lambda {r['lambda_levels'][key]:.0f} with the levels) "
                         + ("kept" if kept else f"-> {value:.3g}")
                         + f" (lambda {r['lambda'][key]:.0f} with the recording)")
        return ", ".join(parts)

    return ("Each planted effect is sized by its lambda with the recording (`Setup.lam`, recorded: the declared "
            "model, its knots chosen from the noise-free recording and fitted with its parameters to the truth; "
            "the lower chi^2 from two starts, the truth's values and the tool's own), scaled on from its size by "
            "the command's levels (the first table's), since the knots absorb part of some effects; kept when "
            "its lambda with the recording is already 100 to 115: " + ", ".join(resized(c, r) for c, r in sized.items())
            + ". The off-library torque pulse loses the most to the knots: at its size by the levels (0.64, "
            "session 10's rows) its lambda with the recording was 43.3 (`python bench/recorded_lambda.py "
            "offlib_torque_pulse 0.6404`)." + _not_resized(rows))


def _not_resized(rows: list[dict]) -> str:
    """The recorded-command rows with a planted effect still at their size by the command's levels."""
    cases = list(dict.fromkeys(r["case"] for r in rows if "error" not in r and r["planted"]
                               and not r.get("lambda_levels")))
    if not cases:
        return ""
    text = (" Not resized (still at the size by the command's levels, session 10's records): "
            + ", ".join(f"`{c}`" for c in cases) + ".")
    if "time_viscous" in cases:
        text += (" `time_viscous`'s seeds take about 5 minutes each, so it was not rerun in session 11; at its "
                 "size (0.00208) its lambda with the recording is 96.6 (`python bench/recorded_lambda.py "
                 "viscous_friction@shaft 0.0020835`), 3 % under the target, where the other rows are at or "
                 "above it.")
    return text


def _recorded_misses(rows: list[dict]) -> str:
    """The recorded-command seeds where a planted effect best by BIC in round 1 was not accepted, and why (the
    reasons its refit was refused, where the record keeps them); then how the rows stood when the held-out
    test compared the bare error (session 9's records, where they are kept)."""
    missed, refits, held_out = _refused(rows)
    text = ("The held-out test here compares the held-out score, not the bare error: a held-out block's knots "
            "are placed by its recording alone, and the score is the Gaussian log score of the block's outputs "
            "under the spread those knots' uncertainty propagates (blocks/calibrate/heldout.py; the right "
            "model's held-out residuals, whitened by it, are at the noise: tests/calibrate/test_heldout_score.py). "
            "The held-out ratio columns are still the bare errors' RMSE. ")
    if missed:
        unexplained = sum(bool(r["unexplained"]) for r in missed)
        text += (f"In {len(missed)} seed{'s' * (len(missed) > 1)} ("
                 + ", ".join(f"{r['case']} {r['seed']}" for r in missed)
                 + ") the planted effect was the best by BIC in round 1 and was not accepted, and the verdict says "
                 f"'unexplained discrepancy remains' in {unexplained} of them.")
        if refits:
            text += (f" Of the {len(refits)} whose record keeps why, {len(held_out)} were refused by the held-out "
                     "test alone" + (f" (dBIC {_span(rf['dbic'] for rf in held_out)}, {_span(rf['z'] for rf in held_out)} "
                               "SE; held-out score with the effect / without it: "
                               + ", ".join(f"{rf.get('heldout_score', float('nan')):.4g}/"
                                           f"{rf.get('base_heldout_score', float('nan')):.4g}" for rf in held_out)
                               + ")" if held_out else "") + ".")
    else:
        text += "In no seed was a planted effect that was best by BIC in round 1 left out."
    return text + " " + _before_the_score(rows)


def _archived(name: str) -> list[dict]:
    return _records(RECORDS / "archive" / name)


def _counts(before: list[dict], after: list[dict]) -> list[str]:
    """Per case in ``after``, its criterion's count in ``before`` -> in ``after`` (right, claimed or
    unexplained)."""
    parts = []
    for case in dict.fromkeys(r["case"] for r in after):
        old = [r for r in before if r["case"] == case and "error" not in r]
        new = [r for r in after if r["case"] == case and "error" not in r]
        if not old:
            continue
        what = {"found": "right", "unexplained": "unexplained"}.get(old[0]["expect"], "claimed")
        count = {"right": lambda rs: sum(all(r["found"]) for r in rs),
                 "claimed": lambda rs: sum(bool(r["accepted"]) for r in rs),
                 "unexplained": lambda rs: sum(bool(r["unexplained"]) for r in rs)}[what]
        parts.append(f"`{case}` {what} {count(old)}/{len(old)} -> {count(new)}/{len(new)}")
    return parts


# Measured history whose records were not committed and went with their checkout (session 13 found out/
# gone): quoted as session 12's table gave it, so that a table written from new records does not drop it.
BEFORE_THE_SCORE_S12 = (
    "As the table of session 12 gave it, from session 9's to 11's records (not committed, since lost): comparing "
    "the bare held-out error instead (session 9's records against session 10's, the same sizes and seeds): "
    "`time_none` claimed 0/20 -> 0/20, `time_coulomb` right 14/20 -> 20/20, `time_extra_volume` right 15/20 -> "
    "19/20, `time_off_library` unexplained 11/20 -> 11/20, `time_sensor_offset` right 20/20 -> 19/20, "
    "`time_viscous` right 17/20 -> 20/20. With the bare error, a planted effect best by BIC in round 1 was left "
    "out in 14 seeds, and of the 14 whose record keeps why, 14 were refused by the held-out test alone, at dBIC "
    "-126 to -56.9: the right model, more sensitive to its command (a friction near standstill), was charged for "
    "the recording's noise. Sized by the command's levels (session 10's records) against sized by the recording "
    "(session 11's; the same seeds, other planted values): `time_off_library` unexplained 11/20 -> 20/20, "
    "`time_coulomb` right 20/20 -> 20/20, `time_extra_volume` right 19/20 -> 19/20, `time_sensor_offset` right "
    "19/20 -> 19/20.")
SCALED_FIT_S12 = (
    "As the table of session 12 gave it (the records from before the change were not committed, since lost): "
    "against those records (the same 820 seeds) the accepted effects changed in 77 seeds, all 77 only between "
    "places reported ambiguous with each other; `steady_leakage` held-out ok 14/20 -> 16/20, and in the rec "
    "column, judged where the planted place itself was accepted, the judged counts moved by one or two, each "
    "row at 100 % before and after; no row's verdict changed. ")


def _before_the_score(rows: list[dict]) -> str:
    """How the rows stood with the bare held-out error compared (session 9's records) against the score
    (session 10's: the same sizes and seeds), and how they stood sized by the command's levels (session
    10's) against their lambda with the recording (now)."""
    s9, s10 = _archived("s9_results_recorded.jsonl"), _archived("s10_results_recorded.jsonl")
    if not s9 or not s10:
        return BEFORE_THE_SCORE_S12
    text = ""
    parts = _counts(s9, s10)
    if parts:
        missed, refits, held_out = _refused(s9)
        text += ("Comparing the bare held-out error instead (session 9's records against session 10's, the same "
                 "sizes and seeds; bench/records/archive/s9_results_recorded.jsonl and "
                 "s10_results_recorded.jsonl): " + ", ".join(parts)
                 + f". With the bare error, a planted effect best by BIC in round 1 was left out in {len(missed)} "
                 f"seeds, and of the {len(refits)} whose record keeps why, {len(held_out)} were refused by the "
                 "held-out test alone" + (f", at dBIC {_span(rf['dbic'] for rf in held_out)}" if held_out else "")
                 + ": the right model, more sensitive to its command (a friction near standstill), was charged "
                 "for the recording's noise. ")
    resized = [r for r in rows if r.get("lambda_levels")]
    parts = _counts(s10, resized)
    if parts:
        text += ("Sized by the command's levels (session 10's records) against sized by the recording (now; the "
                 "same seeds, other planted values): " + ", ".join(parts) + ".")
    return text


def _refused(rows: list[dict]) -> tuple[list[dict], list[dict], list[dict]]:
    """The seeds whose planted effect was best by BIC in round 1 and not accepted; the refits of those
    effects whose record keeps why; those of them refused by the held-out test."""
    missed = [r for r in rows if r["expect"] == "found" and not r["accepted"] and r["rounds"]
              and r["rounds"][0]["best_by_bic"] in r["planted"]]
    refits = [rf for r in missed for rf in r["rounds"][0].get("planted_refits", [])
              if rf["key"] == r["rounds"][0]["best_by_bic"]]
    return missed, refits, [rf for rf in refits if any("held-out" in reason for reason in rf["reasons"])]


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'s' * (n != 1)}"


def _span(values) -> str:
    values = list(values)
    if not values:
        return "-"
    low, high = (f"{v:.3g}" for v in (min(values), max(values)))
    return low if low == high else f"{low} to {high}"


def _median_of(rows: list[dict], key: str) -> str:
    values = [r[key] for r in rows if r.get(key) is not None]
    return f"{np.median(values):.3g} (over {len(values)} seeds)" if values else "-"


def _band_rate(nu: int) -> str:
    """How often chi^2/nu of a right model with nu degrees of freedom falls in [0.8, 1.25]."""
    from scipy import stats

    return f"{100 * (stats.chi2.cdf(1.25 * nu, nu) - stats.chi2.cdf(0.8 * nu, nu)):.0f} %"


def _reference(results: list[dict], case: str, what: str) -> str:
    good = [r for r in results if r["case"] == case and "error" not in r]
    if what == "chi":
        ok = [r["chi2nu_after"] is not None and 0.8 <= r["chi2nu_after"] <= 1.25 for r in good]
    else:
        ok = [r["heldout_ratio"] is not None and r["heldout_ratio"] <= 1.1 for r in good]
    return f"{100 * np.mean(ok):.0f} % ({sum(ok)}/{len(ok)})" if ok else "-"


def _heldout_expected(path: Path, rows: list[dict]) -> str:
    """The held-out criterion against what estimating the right model's parameters costs, per case of a
    records file: the share of seeds within 1.1 x expected (random noise), expected with these seeds' own
    noise, and recorded (from bench/heldout_expected.py's file for ``path``, where its planted values are
    the records')."""
    expected = RECORDS / f"heldout_expected_{path.stem}.json"
    if not expected.exists():
        return ""
    parts = []
    for e in json.loads(expected.read_text()):
        mine = [r for r in rows if r["case"] == e["case"] and r.get("heldout_ratio") is not None]
        if not mine or mine[0]["planted"] != e["planted"]:
            continue
        own = {p["seed"]: p["linear"] for p in e["per_seed"]}
        if sorted(own) != sorted(r["seed"] for r in mine):
            continue
        got = sum(r["heldout_ratio"] <= 1.1 for r in mine)
        parts.append(f"`{e['case']}` {100 * e['expected_share']:.0f} % / {sum(v <= 1.1 for v in own.values())} / "
                     f"{got} of {len(mine)}")
    if not parts:
        return ""
    return (" What the held-out criterion asks of the right model (`python bench/heldout_expected.py"
            + {"results": "", "results_mcv": " --mcv"}.get(path.stem,
                                                           f" --flows {path.stem.removeprefix('results_flows')}")
            + "`: the truth's own structure linearised about the truth, its parameters estimated without each "
            "held-out setting: what the right model itself gets, nonlinearity aside): the share of seeds "
            "within 1.1 x expected under random noise / the seeds within it expected with these seeds' own "
            "noise / the seeds within it recorded: " + ", ".join(parts) + ".")


def _row_name(path: Path, case: str) -> str:
    """A row's name across the records files: `case`, the 60-point `case`, the recorded-command `case`."""
    if path.stem.startswith("results_flows"):
        return f"the {3 * int(path.stem.removeprefix('results_flows'))}-point `{case}`"
    return f"the recorded-command `{case}`" if path.stem == "results_recorded" else f"`{case}`"


def _alike(before: dict, after: dict) -> bool:
    """Whether a seed's accepted effects changed only for places that were reported ambiguous with them,
    before or after (either side of a two-port valve, say)."""
    ambiguous = {key for r in (before, after) for rnd in r["rounds"] for key in rnd["ambiguous"]}
    return set(before["accepted"]) ^ set(after["accepted"]) <= ambiguous


def _section_of(path: Path, kind: str) -> str:
    """The rows of one kind in one records file, as the table's sections name them."""
    if path.stem.startswith("results_flows"):
        return f"every row of the {3 * int(path.stem.removeprefix('results_flows'))}-point section"
    return {"results_recorded": "every row of the recorded-command section",
            "results_mcv": "every row of the MCV rig's section"}.get(
        path.stem, f"every {'time-series' if kind == 'time' else 'steady'} row of the first table")


def _records(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()] if path.exists() else []


def _column_changes(name: str, case: Case, pairs: list[tuple[dict, dict]]) -> list[str]:
    """The table's columns whose count moved between the (before, after) records of the same seeds."""
    columns = (("right", lambda r: all(r["found"]) if case.plants else None),
               ("rec", lambda r: _recovered(case, r)),
               ("chi2/nu ok", lambda r: r["chi2nu_after"] is not None and 0.8 <= r["chi2nu_after"] <= 1.25),
               ("held-out ok", lambda r: r["heldout_ratio"] is not None and r["heldout_ratio"] <= 1.1),
               ("claimed", lambda r: bool(r["accepted"])),
               ("unexpl", lambda r: bool(r["unexplained"])))
    out = []
    for label, judge in columns:
        old = [judge(a) for a, _ in pairs if judge(a) is not None]
        new = [judge(b) for _, b in pairs if judge(b) is not None]
        if pairs and (sum(old), len(old)) != (sum(new), len(new)):
            out.append(f"{name} {label} {sum(old)}/{len(old)} -> {sum(new)}/{len(new)}")
    return out


def _scaled_fit() -> str:
    """Which rows were rerun with the fit's variables scaled (records with ``fit``), what changed against
    their records from before it (archived as s11_<file>_before_scaled_fit.jsonl: the same seeds), and which
    rows are still from before it."""
    rerun, older, changes, moved, alike, seeds = [], [], [], 0, 0, 0
    for path in sorted(RECORDS.glob("results*.jsonl")):
        rows = [r for r in _records(path) if "error" not in r]
        before = {(r["case"], r["seed"]): r for r in _archived(f"s11_{path.stem}_before_scaled_fit.jsonl")}
        groups: dict[str, list[tuple[str, bool]]] = {}  # a section's rows of one kind: (name, rerun)
        for case in CASES:
            mine = [r for r in rows if r["case"] == case.name]
            if not mine:
                continue
            name = _row_name(path, case.name)
            done = all(r.get("fit") in SCALED for r in mine)
            groups.setdefault(_section_of(path, case.kind), []).append((name, done))
            if not done:
                continue
            rerun.append(name)
            pairs = [(before[(case.name, r["seed"])], r) for r in mine if (case.name, r["seed"]) in before]
            seeds += len(pairs)
            changed = [(a, b) for a, b in pairs if sorted(a["accepted"]) != sorted(b["accepted"])]
            moved += len(changed)
            alike += sum(_alike(a, b) for a, b in changed)
            changes += _column_changes(name, case, pairs)
        for section, members in groups.items():
            left = [name for name, done in members if not done]
            older += [f"{section} ({len(left)})"] if len(left) == len(members) else left
    if not rerun:
        return ""
    return ("Session 12 found the fit itself stopping short. scipy's trust-region solver works in the units it "
            "is given, and in SI the parameters differ by 18 orders of magnitude: it moved a start closer than "
            "1e-10 to a bound to 1e-10 from it (a leakage of 2e-11 m^3/(s*Pa) to 1e-10: in `steady_leakage` "
            "seed 15 a held-out fold's refit then did not converge in 100 evaluations and its held-out ratio "
            "was 2.27, where the linearised right model gives 0.94), and its step tolerance, taken over the "
            "whole SI vector, reported fits converged while the small parameters still moved. The solver now "
            "works on each parameter divided by its own size (blocks/calibrate/fit.py). Rerun with it: "
            + ", ".join(rerun) + ". " + ((f"Against their records from before it (the same {seeds} seeds; "
            "bench/records/archive/s11_*_before_scaled_fit.jsonl) the accepted effects changed in "
            f"{moved} seeds ({alike} of them only between places reported ambiguous with each other)"
            + ("; " + ", ".join(changes) if changes else ", and no column's count changed") + ". ") if seeds else
            SCALED_FIT_S12)
            + (("Still from before it (not rerun): " + ", ".join(older) + ".") if older else "")).strip()


def _restarts() -> str:
    """What the further starts of the refits near the best (session 13) did in the records made with them:
    seeds where one lowered a refit's chi^2 by over 1, and seeds where that changed a round's best by BIC."""
    seeds, lowered, reranked, tied, alike, alike_reranked = 0, {}, {}, {}, 0, 0
    for path in sorted(RECORDS.glob("results*.jsonl")):
        for r in _records(path):
            if r.get("fit") != "restarts" or "error" in r:
                continue
            seeds += 1
            name = _row_name(path, r["case"])
            if any(f["dbic_first_start"] - f["dbic"] > 1.0 for rnd in r["rounds"] for f in rnd.get("refits") or []):
                lowered[name] = lowered.get(name, 0) + 1
            changes = [c for c in map(_rerank, r["rounds"]) if c is not None]
            if any(margin > 1.0 for margin, _ in changes):
                reranked[name] = reranked.get(name, 0) + 1
                alike_reranked += all(ambiguous for margin, ambiguous in changes if margin > 1.0)
            elif changes:
                tied[name] = tied.get(name, 0) + 1
                alike += all(ambiguous for _, ambiguous in changes)
    if not seeds:
        return ""

    def listed(counts: dict) -> str:
        return (_count(sum(counts.values()), "seed") + " (" + ", ".join(f"{k} {v}" for k, v in counts.items())
                + ")" if counts else "no seed")

    def among_ambiguous(counts: dict, n: int) -> str:
        return f", {n} of them between places the round reports ambiguous with each other" if counts else ""

    return ("Session 13: a candidate's refit from one start (its linearised estimate) can end in a local "
            "minimum; on the MCV's real data a p1 sensor gain ended at chi^2 603.8, from 1.5 times its value at 589.0. "
            "Every refit that passes the fit tests within 30 in BIC of the best one that passes is now tried from two "
            "more starts "
            "(the candidate's parameter at 0.5 and 1.5 of its first value, the rest where the first ended; "
            f"blocks/calibrate/selection.py) and the lowest chi^2 counts. In the {seeds} seeds recorded with it, "
            f"a further start lowered a refit's chi^2 by over 1 in {listed(lowered)}; it changed a round's best "
            f"by BIC by over 1 in {listed(reranked)}{among_ambiguous(reranked, alike_reranked)}, and by 1 or less "
            f"in {listed(tied)}{among_ambiguous(tied, alike)}.")


def _stuck_refits() -> str:
    """The seeds rerun (session 14) because a refit had ended worse than its candidate at zero, against their
    records from before (archived as s13_<file>_before_retreat.jsonl): what changed, and how the refits that
    moved by over 1 in BIC moved."""
    pairs, names, before_dbic, after_dbic, changes = [], [], [], [], []
    for path in sorted(RECORDS.glob("results*.jsonl")):
        now = {(r["case"], r["seed"]): r for r in _records(path) if "error" not in r}
        before = [r for r in _archived(f"s13_{path.stem}_before_retreat.jsonl") if (r["case"], r["seed"]) in now]
        for case in CASES:
            mine = [(r, now[(r["case"], r["seed"])]) for r in before if r["case"] == case.name]
            if not mine:
                continue
            name = _row_name(path, case.name)
            names.append(f"{name} " + ", ".join(str(a["seed"]) for a, _ in mine))
            changes += _column_changes(name, case, mine)
            pairs += mine
            for a, b in mine:
                for ra, rb in zip(a["rounds"], b["rounds"]):
                    after = {f["key"]: f["dbic"] for f in rb.get("refits") or []}
                    for f in ra.get("refits") or []:
                        if f["key"] in after and abs(after[f["key"]] - f["dbic"]) > 1.0:
                            before_dbic.append(f["dbic"])
                            after_dbic.append(after[f["key"]])
    if not pairs:
        return ""
    moved = sum(sorted(a["accepted"]) != sorted(b["accepted"]) for a, b in pairs)
    return ("Session 14: a refit from the candidate's linearised estimate could stop where it started, worse "
            "than the candidate at its zero. Far out, the model may not run (a turbulent loss in a refill valve's "
            "line, linearised to k = 3e19 Pa*s^2/m^6, closes the line and the solver's step falls below its "
            "minimum: every residual holds the failure value, 1e3, and such refits were listed at dBIC 6.8e9 "
            "with no word of why), or its outputs may no longer move with the parameter. A refit that ends over "
            "1 in chi^2 worse than its candidate at zero is now started again 10 times nearer the zero, until it "
            "does not (at most 6 times), and a refit with runs failing at its end that do not fail with the "
            "candidate at zero is refused, saying so "
            "(blocks/calibrate/selection.py). The seeds whose records had such a refit were rerun with it: "
            + "; ".join(names) + ". Against their records from before it (the same " + _count(len(pairs), "seed")
            + "; bench/records/archive/s13_*_before_retreat.jsonl) the accepted effects changed in "
            + _count(moved, "seed") + ("; " + ", ".join(changes) if changes else ", and no column's count changed")
            + (f"; the {_count(len(after_dbic), 'refit')} whose dBIC moved by over 1 had dBIC "
               f"{_span(before_dbic)} before and {_span(after_dbic)} now" if after_dbic else "") + ".")


RERUNS = (  # (archive, what changed): each a paragraph of the table's versions, from its seeds' reruns
    ("s21_breakpoints.jsonl",
     "Session 21: the solver lands a step on each time an input jumps or kinks (a step's time, a profile's "
     "points where its slope changes; blocks/solve/rosenbrock.py). Before, a step could be longer than a "
     "pulse of the input and pass over it unseen. The records above were made before it."),
    ("s22_proportional.jsonl",
     "Session 22: the screening calls a candidate whose change of the outputs is not proportional to its "
     "size (half the step, not half the change: a jump, or the solver's noise) 'no effect' instead of "
     "scoring it (blocks/calibrate/screening.py; a user's steady rig had an extra volume, which moves no "
     "equilibrium, scored T = 14). Compared with the records above, or with session 21's reruns where "
     "there are some: the recorded-command seeds but `time_coulomb` 1 were not rerun in session 21, so their "
     "differences carry its solver change too (a breakpoint at each point of the recording's profile; the "
     "accepted effects are the same, so the final fits differ by the solver alone). These seeds ran the "
     "check's first version, which called a change not proportional at its first step 'no effect' at once."),
    ("s22_retry.jsonl",
     "The check's final version (a review showed, on a model of its own, that the first would call a strong "
     "transport delay 'no effect': its "
     "step had ended at 1e-5 s, and half of it, under the delay's shortest 1e-5 s, passes the input through) "
     "tries such a change again at 10 times its step and scores it there if it is first order. Compared with "
     "the same records."),
    ("s24_dahl.jsonl",
     "Session 24: the relief rig's spool friction (Dahl's model) followed a smoothed sign of the spool's speed, "
     "u'/sqrt(u'^2 + w^2), which settles the friction state at sqrt(u'^2 + w^2)/u' > 1, so that a spool creeping "
     "to rest held more than p_fric (a physics audit found it; blocks/library/hydraulic/spool_relief_valve.py "
     "now has Dahl's exact law, |z| <= 1). It moves the truth where spool friction is planted (lambda at the "
     "recorded size 104.7 -> 103.7, with 60 points 107.2 -> 106.3) and the spool-friction candidate in every "
     "steady seed. Compared with the records above, or with the latest rerun where there is one."),
    ("s27_ties_packages.jsonl",
     "Session 27: the records were made on earlier versions of numba, llvmlite, numpy and scipy than this "
     "machine's (0.68.1, 0.50.0, 2.4.6, 1.17.1), and a rerun on them chose the other port of one element for a "
     "line loss (seed 1 of `steady_line_loss_turbulent`: meter.a -> meter.b), the two places being equal to the "
     "last digits (dBIC -116.44409958048 and -116.44409958049). Such ties are now broken by name "
     "(blocks/calibrate/selection.py: refits within 0.01 in BIC and screening scores within 1e-6 of each other "
     "are taken in the order of their place keys; so are the elimination's and the exchange's best), so that the "
     "same data give the same report on every machine. These reruns carry both changes "
     "(`python bench/rerun_seeds.py s27_ties_packages.jsonl ...`). The recorded-command rows moved far more "
     "than the others: their fits, which fit the latent trace's knots with the parameters, stop on the solver's "
     "step tolerance before their minimum, and where they stop follows the last digits. The code of session 22 "
     "(commit 4a443c4) on this machine gives the recorded-command `time_none` seed 1 exactly as the code now "
     "does (chi^2/nu 0.9946730554537146, against 0.99354 on the earlier packages), so the packages moved it, not "
     "the code since; and that seed's final fit restarted from where it stopped lowers its chi^2 from 6741.9 to "
     "6735.6, and no further on more restarts. In the recorded-command `time_viscous` seed 1 the viscous friction "
     "and a laminar loss in the motor's line (both a torque growing with the speed) changed places at the head "
     "of round 1, each reported ambiguous with the other before and after (dBIC -89.8 and -88.3 before, -84.5 "
     "and -86.5 now). Compared with the records above, or with the latest rerun where there is one."),
)


def _reruns() -> str:
    return " ".join(p for p in (_rerun_paragraph(name, intro) for name, intro in RERUNS) if p)


def _rerun_paragraph(archive: str, intro: str) -> str:
    """A change against the records made before it: the seeds rerun with it (bench/records/archive/``archive``
    holds each seed's record and its rerun, the compared keys)."""
    rows = _archived(archive)
    if not rows:
        return ""
    names = {}
    for r in rows:
        names.setdefault(_row_name(RECORDS / r["file"], r["case"]), []).append(str(r["seed"]))
    moved = [r for r in rows if sorted(r["before"]["accepted"]) != sorted(r["after"]["accepted"])]
    judged = [r for r in rows if r["before"]["found"] != r["after"]["found"]]
    verdicts = [r for r in rows if r["before"]["unexplained"] != r["after"]["unexplained"]]

    def most(key: str, rows: list[dict] = rows) -> str:
        return f"{max(abs(r['after'][key] - r['before'][key]) for r in rows):.2g}"

    def shifts(rows: list[dict]) -> list[float]:
        return [abs(r["after"]["estimates"][k][0] - value) / se for r in rows
                for k, (value, se) in (r["before"]["estimates"] or {}).items()
                if k in (r["after"]["estimates"] or {}) and se]

    def moved_by(rows: list[dict]) -> str:
        moved_se = shifts(rows)
        return ("chi^2/nu moved by at most " + most("chi2nu_after", rows) + ", the held-out ratio by at most "
                + most("heldout_ratio", rows) + ", an estimate by at most "
                + (f"{max(moved_se):.2g}" if moved_se else "0") + " of its standard error")

    # where one records file's rows moved far more than the others' (over 100 times in chi^2/nu), each is said
    files = {}
    for r in rows:
        files.setdefault(r["file"], []).append(r)
    spread = {f: max(abs(r["after"]["chi2nu_after"] - r["before"]["chi2nu_after"]) for r in group)
              for f, group in files.items()}
    apart = len(files) > 1 and max(spread.values()) > 100 * max(min(spread.values()), 1e-12)
    changes = "; ".join(f"{_row_name(RECORDS / r['file'], r['case'])} {r['seed']}: "
                        f"{', '.join(sorted(r['before']['accepted']))} -> {', '.join(sorted(r['after']['accepted']))}"
                        for r in moved)
    return (intro + " Rerun with it (" + "; ".join(f"{name} {', '.join(seeds)}" for name, seeds in names.items())
            + f"; bench/records/archive/{archive} holds each seed's record and its rerun): the "
            "accepted effects changed in " + _count(len(moved), "seed") + (f" ({changes})" if moved else "")
            + _why_moved(moved)
            + ", the right column's judgement in " + _count(len(judged), "seed") + ", the verdict in "
            + _count(len(verdicts), "seed") + "; "
            + ("; ".join(f"{_file_rows(f)}: {moved_by(group)}" for f, group in files.items()) if apart
               else moved_by(rows)) + ".")


def _file_rows(file: str) -> str:
    """The rows of one records file, as a rerun paragraph names them."""
    return {"results.jsonl": "the first table's rows",
            "results_mcv.jsonl": "the MCV rig's rows", "results_recorded.jsonl": "the recorded-command rows"}.get(
        file, f"the {3 * int(file.removeprefix('results_flows').removesuffix('.jsonl'))}-point rows"
        if file.startswith("results_flows") else file)


DELAY_SIDES = ("a delay on the command u and one on the spool's output xs, on either side of the spool's linear "
               "filter, give the same response")
PORT_SIDES = ("a loss in series on either side of it, the same flow through it, is the same effect")


def _why_moved(moved: list[dict]) -> str:
    """Why the accepted effects of rerun seeds changed where a change is between equivalent places: a transport
    delay on either side of the spool's filter, or a loss at the other port of one element (the others, if
    any, are for the paragraph's intro to say)."""
    delays = [r for r in moved if _delay_sides(r)]
    ports = [r for r in moved if _other_port_only(r) and r not in delays]
    if len(delays) == len(moved) > 0:
        return f" ({DELAY_SIDES})"
    if len(ports) == len(moved) > 0:
        return f" (each between the two ports of one element: {PORT_SIDES})"
    said = ([f"the losses that moved between the two ports of one element: {PORT_SIDES}"] if ports else []) + (
        [f"the delays that moved between u and xs: {DELAY_SIDES}"] if delays else [])
    return f" ({'; '.join(said)})" if said else ""


def _delay_sides(row: dict) -> bool:
    return {"transport_delay@u", "transport_delay@xs"} <= set(row["before"]["accepted"]) | set(row["after"]["accepted"])


def _other_port_only(row: dict) -> bool:
    """Whether a rerun's accepted effects differ from its record's only by the port of one element they sit
    at (line_loss_turbulent@meter.b -> line_loss_turbulent@meter.a)."""
    before, after = set(row["before"]["accepted"]), set(row["after"]["accepted"])

    def element(key: str) -> tuple[str, str]:
        candidate, _, place = key.partition("@")
        return candidate, place.rsplit(".", 1)[0]

    gone, new = sorted(map(element, before - after)), sorted(map(element, after - before))
    return bool(gone) and gone == new and all("." in k.partition("@")[2] for k in before ^ after)


def _rerank(rnd: dict) -> tuple[float, bool] | None:
    """None if a round's best by BIC is the same from the first starts alone as from all; else by how much
    the new best beats the old best (both after their further starts), and whether the round reports one of
    the two ambiguous with the other."""
    refits = rnd.get("refits") or []
    if not refits:
        return None
    old = min(refits, key=lambda f: f["dbic_first_start"])
    new = min(refits, key=lambda f: f["dbic"])
    if old["key"] == new["key"]:
        return None
    return old["dbic"] - new["dbic"], bool({old["key"], new["key"]} & set(rnd["ambiguous"]))


def _after_trace_effect() -> str:
    """What the checks after the trace changed in the rows rerun with them: seeds with an exchange made and
    seeds with an effect removed, per case."""
    made: dict[str, int] = {}
    removed: dict[str, int] = {}
    for path in sorted(RECORDS.glob("results*.jsonl")):
        for r in _records(path):
            name = _row_name(path, r.get("case"))
            if any(e["made"] for e in r.get("exchanges", [])):
                made[name] = made.get(name, 0) + 1
            if any(t["removed"] for t in r.get("removals", [])):
                removed[name] = removed.get(name, 0) + 1

    def counted(tally: dict[str, int]) -> str:
        return ", ".join(f"{n} seed{'s' * (n > 1)} of {c}" for c, n in tally.items())

    return ((f"The exchange check made an exchange in {counted(made)}" if made
             else "The exchange check made no exchange in any seed")
            + (f"; the elimination check removed an effect in {counted(removed)}." if removed
               else "; the elimination check removed no effect in any seed."))


def _chance_claim(results: list[dict], case: str, n: int) -> str:
    """How often the planted effect of ``case`` (lambda ~ 3) passes dBIC < -10 by its noise alone: its chi^2
    drop on refitting is non-central chi^2_1(lambda), over 10 + ln n with n residual rows; and the chance of
    at least one such seed in 20."""
    lam = next((sum(r["lambda"].values()) for r in results if r["case"] == case and "error" not in r), None)
    if lam is None:
        return "-"
    from scipy.stats import ncx2

    rate = float(ncx2.sf(10.0 + np.log(n), 1, lam))
    return (f"{100 * rate:.1f} % of seeds (lambda {lam:.2g}, n = {n}; in at least one of 20 seeds: "
            f"{100 * (1 - (1 - rate) ** 20):.0f} %)")


def _linear_sensor_leftover(results: list[dict]) -> str:
    """What a p3 gain and offset leave of the MCV rig's curved p3 sensor: in the seeds that accepted both
    (nothing else), the mean of chi^2 - nu of the final fit (its non-centrality, nu = 41 - 2), and how often
    the verdict still said 'unexplained'."""
    both = [r for r in results if r["case"] == "mcv_off_library" and "error" not in r
            and sorted(r["accepted"]) == ["sensor_gain@p3", "sensor_offset@p3"]]
    if not both:
        return "-"
    from scipy.stats import chi2, ncx2

    left = float(np.mean([39 * r["chi2nu_after"] - 39 for r in both]))
    power = float(ncx2.sf(chi2.isf(0.01 / 4, 2), 2, max(left, 1e-9)))
    return (f"in the {len(both)} seeds that accepted a p3 gain and offset (and nothing else), the final chi^2 "
            f"exceeds nu by {left:.0f} on average, of lambda 106, and the verdict says 'unexplained' in "
            f"{sum(r['unexplained'] for r in both)} of them. Even all of that leftover on the structure test's "
            f"two degrees of freedom is found at its level (0.01 over 4 tests) with a probability of "
            f"{power:.2f}")


def rec_misses(results: list[dict]) -> list[str]:
    """A line per case whose rec column has misses: how many of those seeds had an ambiguous alternative
    accepted in place of another planted effect (the estimate is then that of a different model, and the
    report names the parameters the choice moves)."""
    lines = []
    for case in CASES:
        rows = [r for r in results if r["case"] == case.name and "error" not in r]
        missed = [r for r in rows if _recovered(case, r) is False]
        if not missed:
            continue
        planted = {p.key for p in case.plants}
        swapped = [r for r in missed if not planted <= set(r["accepted"])]
        instead = sorted({a for r in swapped for a in r["accepted"] if a not in planted})
        reported = [r for r in swapped if any(key in rnd["ambiguous"] for rnd in r["rounds"]
                                              for key in planted - set(r["accepted"]))]
        head = f"- `{case.name}`: {len(missed)} seed{'s' * (len(missed) > 1)} missed by over 3 SE"
        if case.expect == "nothing_claimed":
            lines.append(f"{head}: a claim at lambda <= 3 is selected by its noise, which biases its estimate "
                         f"away from zero.")
        elif not swapped:
            lines.append(f"{head}, with the planted model itself accepted.")
        else:
            lines.append(f"{head}; {len(swapped)} of them accepted an alternative in place of a planted effect "
                         f"({', '.join(instead)}), with the missing planted effect reported ambiguous with it in "
                         f"{len(reported)}: the estimate is then that of a different model.")
    return ["Misses in the rec column:", ""] + lines if lines else []


def _recovered(case: Case, r: dict):
    """All planted parameters within 3 SE, judged only where the planted place itself was accepted (an
    ambiguous alternative has a parameter of other meaning); None when none was."""
    accepted = set(r["accepted"])  # the final model's effects
    judged = [rec for plant, rec in zip(case.plants, r["recovered"]) if plant.key in accepted and rec is not None]
    return all(judged) if judged else None


def sized_otherwise(case: str, values: dict[str, float], records: list[dict]) -> str | None:
    """Why the records of ``case`` cannot be joined by new seeds at the sizes ``values`` (a row must be
    of one size), or None: a record planted at other values (e.g. sized by another lambda)."""
    for r in records:
        if r["case"] != case or "error" in r:
            continue
        old = r["planted"]
        if set(old) != set(values) or any(not np.isclose(old[k], values[k], rtol=1e-9, atol=0.0) for k in values):
            return (f"the records of {case} (seed {r['seed']}) planted {old}, the sizing now gives {values}; a row "
                    f"must be of one size")
    return None


def would_lose(committed: str) -> list[str]:
    """What of the committed table a table written from the records now present would not have: each section
    of ``committed`` names its records file (its 'Records:' line), each row its case and its seeds, and a
    section that quotes what the held-out criterion asks of the right model needs bench/heldout_expected.py's
    file. A table is written only when this is empty, so a checkout without some records, or a run cut short
    (one seed of every case), never replaces a section's measured rows by fewer."""
    lost, rows, quotes = [], [], False
    seeds_column = None
    for line in committed.splitlines():
        cells = [c.strip() for c in line.split("|")[1:-1]]
        if line.startswith("| case "):
            seeds_column = cells.index("seeds")
        elif line.startswith("| ") and not line.startswith("|---") and seeds_column is not None:
            rows.append((cells[0], int(cells[seeds_column])))
        quotes = quotes or "What the held-out criterion asks of the right model" in line
        found = re.search(r"[Rr]ecords: \S*?(results\w*\.jsonl)", line)
        if found:
            path = RECORDS / found[1]
            have: dict[str, int] = {}
            for r in _records(path):
                have[r["case"]] = have.get(r["case"], 0) + ("error" not in r)
            short = [f"{case} ({have.get(case, 0)} of {n} seeds)" for case, n in rows if have.get(case, 0) < n]
            if short:
                lost.append(f"{found[1]}: {', '.join(short)}")
            expected = RECORDS / f"heldout_expected_{path.stem}.json"
            if quotes and not expected.exists():
                lost.append(f"{expected.name} (run bench/heldout_expected.py)")
            rows, quotes = [], False
    return lost


def write_table() -> bool:
    """Write the table from the records; refuse (and say what is missing) if it would drop committed rows."""
    from blocks.result import atomic_write_text

    main = RECORDS / "results.jsonl"  # the main table's, whatever --flows this run had
    results = _records(main)
    lost = would_lose(TABLE.read_text()) if TABLE.exists() else []
    if lost:
        partial = OUT / "table_partial.md"
        atomic_write_text(partial, table(results))
        print(f"not writing {TABLE}: {RECORDS} lacks what it shows: " + "; ".join(lost) + f"; the table of "
              f"the records there is in {partial}", file=sys.stderr)
        return False
    atomic_write_text(TABLE, table(results))
    print(f"wrote {TABLE}")
    return True


# ---- the example data files -------------------------------------------------------------------------------
def examples() -> None:
    """The committed example data: the relief rig with relief.c_ff = 0.3, the drive line with Tc = 3 N*m."""
    from blocks.circuit import Circuit

    for kind, key, value, target in (("steady", "flow_force@relief", 0.3, "relief_rig_steady.csv"),
                                     ("time", "coulomb_friction@shaft", 3.0, "drive_line_series.csv")):
        s = setup(kind)
        plants = {key: value}
        clean = s.truth_data(Circuit.from_file(s.truth_netlist(plants, f"example_{kind}")), plants)
        rng = np.random.default_rng(1)
        noisy = {k: v + rng.normal(size=v.shape) * s.sigma[k] for k, v in clean.items()}
        path = EXPERIMENTS / "data" / target
        write_data(s, noisy, path)
        text = path.read_text().replace(
            "# Monte Carlo data (synthetic)",
            f"# SYNTHETIC data written by bench/calibrate_mc.py --examples (seed 1): the netlist of the experiment\n"
            f"# with {key} = {value:g} (SI) and Gaussian noise on every column (sigma as in the experiment file).")
        path.write_text(text)
        print(f"wrote {path}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--cases", nargs="*", help="case names (default: all)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--flows", type=int, help="steady cases only: this many flows per setting instead of 7 "
                                                  "(results in their own file and table section)")
    parser.add_argument("--recorded", action="store_true", help="time-series cases only: the command imposed as its "
                                                                  "recording, a latent trace (results in their own "
                                                                  "file and table section)")
    parser.add_argument("--table", action="store_true", help="only write the table from the results so far")
    parser.add_argument("--examples", action="store_true", help="rewrite the example data files")
    args = parser.parse_args(argv)
    if args.flows is not None and args.flows < 2:
        parser.error(f"--flows {args.flows}: give at least 2 flows per setting")
    if args.examples:
        examples()
        return 0
    if args.table:
        return 0 if write_table() else 2
    OUT.mkdir(parents=True, exist_ok=True)
    RECORDS.mkdir(parents=True, exist_ok=True)
    if args.flows is not None and args.recorded:
        parser.error("--flows is for the steady cases, --recorded for the time series: give one")
    configure(args.flows, args.recorded)
    records = load_results()
    done = {(r["case"], r["seed"]) for r in records}
    cases = [c for c in CASES if (not args.cases or c.name in args.cases) and (not args.flows or c.kind == "steady")
             and (not args.recorded or c.kind == "time")
             and (c.kind != "mcv" or args.cases)]  # the MCV rig's cases run when named
    jobs = []
    for case in cases:
        seeds = [s for s in range(args.first_seed, args.first_seed + args.seeds) if (case.name, s) not in done]
        if not seeds:
            continue
        if case.name not in _SIZES:
            started = time.perf_counter()
            _SIZES[case.name] = setup(case.kind).size(case)
            print(f"{case.name}: sized {_SIZES[case.name]} in {time.perf_counter() - started:.0f} s", flush=True)
        stale = sized_otherwise(case.name, _SIZES[case.name][0], records)
        if stale:
            print(f"error: {results_file(case.kind)}: {stale}; move that case's records out (e.g. to "
                  f"{RECORDS / 'archive'}) to rerun it at the new size", file=sys.stderr)
            return 2
        jobs += [(case.name, s, _SIZES[case.name], args.flows, args.recorded) for s in seeds]
    jobs.sort(key=lambda job: job[1])  # seed by seed over the cases: an interrupted run covers every case
    print(f"{len(jobs)} runs", flush=True)
    import multiprocessing

    with ProcessPoolExecutor(max_workers=args.workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = [pool.submit(_worker, job) for job in jobs]
        for fut in as_completed(futures):
            result = fut.result()
            kind = next(c.kind for c in CASES if c.name == result["case"])
            with open(results_file(kind), "a") as handle:
                handle.write(json.dumps(result, default=float) + "\n")
            summary = result.get("error") or (f"accepted {result['accepted']}, chi2/nu {result['chi2nu_after']:.3g}, "
                                              f"held-out ratio {result['heldout_ratio']}, {result['seconds']:.0f} s")
            print(f"{result['case']} seed {result['seed']}: {summary}", flush=True)
    if write_table():
        return 0
    files = sorted({str(results_file(case.kind)) for case in cases})
    print(f"the run's records are in {', '.join(files)}; the table was not rewritten", file=sys.stderr)
    return 2  # the records stand, but a script must not take the committed table for this run's


if __name__ == "__main__":
    sys.exit(main())
