"""Why a case of the diagnosis study is hard: how large a hidden cause's signal is beside the
truth's own differences from the model, and how alike their shapes are.

For a scenario of the study (:mod:`validate.studies.diagnosis_cases`, ``--quick`` grids) and the
C-frame's default model on ``resolution`` (the study's model mesh, ``default``), per channel group
(temperatures [K], probes [um]):

* the *signal* of a cause: y(model with the cause) - y(model), RMS over channels and samples;
* the *materials*: y(model with the truth's conductivity and heat capacity, :data:`validate.synthetic.PERTURBED`
  without its expansion, which the diagnosis fits as a bounded nuisance) - y(model): a difference
  the diagnosis does not fit and its model-error estimate does not contain;
* the *estimate*: y(on the study's error mesh, ``coarse``) - y(model), the diagnosis's signed
  model-error estimate;
* corr(a, b) = sum a b / sqrt(sum a^2 sum b^2) over the group's channels and samples: 1 is the
  same shape.

``python -m validate.studies.diagnosis_signals`` prints these for the causes the study's failures
turned on (the skin film x1.3 and 60 W on the column's right side on the heat-cool test; a 5 W/K
test-bar seat and the same 60 W on the duty cycle; the rotating bar's film x0.6 against the front
bearing x1.2 on the heat-cool test). About 10 twin runs on the default mesh: 3-6 min on 2 idle cores.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from learners.metrics import rms
from validate.studies.common import cli_parser, run_cli

MESHES = ("coarse", "default", "fine")

CAUSES = {
    "spindle-heat-cool-9000": ("ambient_convection.h x1.3", "column.+x 60 W", "spindle_forced_convection.h_reference x0.6",
                               "spindle_bearings.front_power x1.2"),
    "spindle-duty-cycle": ("test_bar_contact 5 W/K", "column.+x 60 W"),
}


def correlation(a: np.ndarray, b: np.ndarray) -> float:
    """sum a b / sqrt(sum a^2 sum b^2) (0 when either is zero)."""
    den = float(np.sqrt(np.sum(a * a) * np.sum(b * b)))
    return float(np.sum(a * b) / den) if den > 0 else 0.0


def cause_spec(spec, machine, cause: str):
    """The model ``spec`` with ``cause``: 'effect.parameter xF' (an uncertain parameter F times its
    model value), 'test_bar_contact 5 W/K' (the missing seat) or 'column.+x 60 W' (the study's
    outside source on that region, registered as a custom effect)."""
    from twin.effects import EFFECTS
    from twin.model import ModelSpec
    from validate.candidates import missing_effect, wrong_parameters
    if " x" in cause:
        name, factor = cause.rsplit(" x", 1)
        c = next(c for c in wrong_parameters(spec, machine) if c.name == name)
        return c.spec(spec, c.zero * float(factor))
    if cause.startswith("test_bar_contact"):
        return missing_effect("test_bar_contact").spec(spec, 5.0)
    from twin.effects.custom import effects_from_dict, register_custom
    from validate.studies.diagnosis_cases import OUTSIDE
    region, kind, strength, schedule, _ = next(o for o in OUTSIDE if o[0] == cause.split()[0])
    if "outside_source" not in EFFECTS:
        register_custom(effects_from_dict({"effects": {"outside_source": {
            "kind": kind, "region": region, "power": strength, "schedule": schedule}}}, "diagnosis_signals", machine))
    params = {g: dict(v) for g, v in spec.params.items()}
    params["outside_source"] = EFFECTS["outside_source"].defaults()
    return ModelSpec(tuple(spec.effects) + ("outside_source",), params)


def signals(scenario: str, causes, resolution: str = "default", error_mesh: str = "coarse") -> dict:
    """{group: {"materials": rms, "estimate": rms, cause: (rms, corr with materials, corr with
    estimate), ("corr", a, b): corr}} on the study's quick grid of ``scenario``."""
    from geometries import build_machine
    from geometries.materials import MATERIALS
    from twin.model import default_spec
    from twin.physics.prepared import PreparedTwin
    from validate.signatures import Engine
    from validate.studies.diagnosis_cases import load_case_scenario
    from validate.synthetic import PERTURBED
    machine = build_machine("cframe-vmc")
    sc = load_case_scenario(scenario, True)
    spec = default_spec(machine)
    thermal = {m: replace(v, expansion=MATERIALS[m].expansion) for m, v in PERTURBED.items()}
    model = Engine(machine, sc, resolution)
    y0 = model.observe(spec)
    materials = Engine(machine, sc, prepared=PreparedTwin(machine, None, resolution, thermal)).observe(spec) - y0
    estimate = Engine(machine, sc, error_mesh).observe(spec) - y0
    moved = {c: model.observe(cause_spec(spec, machine, c)) - y0 for c in causes}
    groups = np.array(model.groups)
    out = {}
    for g in ("temperature", "probe"):
        k = groups == g
        row = {"materials": float(rms(materials[:, k])), "estimate": float(rms(estimate[:, k]))}
        for c, d in moved.items():
            row[c] = (float(rms(d[:, k])), correlation(d[:, k], materials[:, k]), correlation(d[:, k], estimate[:, k]))
        names = list(moved)
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                row[("corr", a, b)] = correlation(moved[a][:, k], moved[b][:, k])
        out[g] = row
    return out


def main(argv=None) -> int:
    ap = cli_parser("python -m validate.studies.diagnosis_signals", __doc__)
    ap.add_argument("--resolution", default="default", choices=MESHES, help="the model's mesh (default: %(default)s)")
    ap.add_argument("--error-mesh", default="coarse", choices=MESHES,
                    help="the model-error estimate's mesh, another than --resolution (default: %(default)s)")
    return run_cli(ap.parse_args, argv, _run)


def _run(a) -> int:
    from twin.errors import InputError

    if a.error_mesh == a.resolution:
        raise InputError("command line", "--error-mesh", f"{a.error_mesh} is the model's own mesh (--resolution): it "
                                                         "must be another resolution")
    unit = {"temperature": "K", "probe": "um"}
    for scenario, causes in CAUSES.items():
        res = signals(scenario, causes, a.resolution, a.error_mesh)
        print(f"{scenario} (quick grid), model on {a.resolution}:")
        for g, row in res.items():
            print(f"  {g}: materials {row['materials']:.3g} {unit[g]}, estimate {row['estimate']:.3g} {unit[g]} RMS")
            for c in causes:
                size, cm, ce = row[c]
                print(f"    {c}: {size:.3g} {unit[g]} RMS, corr with materials {cm:+.2f}, with estimate {ce:+.2f}")
            for key, v in row.items():
                if isinstance(key, tuple):
                    print(f"    corr({key[1]}, {key[2]}) {v:+.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
