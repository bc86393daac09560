"""What the single reference pose costs: ``seed003-exp1`` on meshes built with the Y axis at the
ends of its stroke against the mesh at the reference pose, and the read-out at the pose of the
measurement (:mod:`twin.observe.pose`) against meshes built at that pose.

Read-out (:func:`hold_scenario`): the spindle running and Y reciprocating, then holding at each
pose of ``--poses``, on the mesh built at that pose (the truth: nothing is carried there) and on the
reference-pose mesh read at the mesh's pose (the old read-out) and at the axis's pose (the new
one); printed: the largest differences of the tool-point drift and the five probes [um].

``python -m validate.studies.axis_pose [--quick] [--poses "60 mm,340 mm"]`` runs ``cframe-vmc`` with its
feed drive on ``seed003-exp1`` three times, the saddle and table built at Y = p_ref (200 mm) and at
each pose of ``--poses`` (lengths with their unit) (:func:`geometries.axes.at_pose`), and prints per pose the largest
change of the thermal slope k - k0 [um/mm], of the error at the last target [um], of the sites'
temperatures [K] and of the tool-point drift [um].
"""

from __future__ import annotations

import argparse

import numpy as np

from validate.studies.common import cli_parser, run_cli

SCENARIO = "seed003-exp1"


def run_at(machine, scenario, resolution: str):
    """The result Dataset of ``scenario`` on ``machine`` (built at some pose) with the interferometer."""
    from twin.io.results import to_dataset
    from twin.model import default_spec
    from twin.observe import standard_observers
    from twin.observe.interferometer import LaserInterferometer
    from twin.simulate import run

    observers = standard_observers(machine) + [LaserInterferometer(scenario.interferometer, machine)]
    return to_dataset(run(machine, scenario, default_spec(machine), resolution=resolution, observers=observers), 0,
                      resolution)


HOLD_SPEED, WARM, HOLD = "6000 rpm", 110.0, 10.0   # spindle speed; minutes reciprocating, then holding


def hold_scenario(axis: str, p_mm: float, travel_mm: tuple[float, float]):
    """The spindle at :data:`HOLD_SPEED`; ``axis`` reciprocating over ``travel_mm`` at 20 mm/s for
    :data:`WARM` minutes (its drive heats the structure under the body), then moving to ``p_mm``
    [mm] and holding there to the end (:data:`HOLD` minutes), where the read-out is compared."""
    from twin.scenario import scenario_from_dict
    lo, hi = travel_mm
    moves = [{"kind": "reciprocate", "between": [f"{lo:g} mm", f"{hi:g} mm"], "feed": "20 mm/s",
              "acceleration": "10 mm/s2", "duration": f"{WARM:g} min"},
             {"kind": "move", "to": f"{p_mm:g} mm", "feed": "20 mm/s", "acceleration": "10 mm/s2",
              "duration": f"{HOLD:g} min"}]
    return scenario_from_dict({"sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
                               "spindle": [{"speed": HOLD_SPEED, "duration": f"{WARM + HOLD:g} min"}],
                               "axis": [{"name": axis, "start": f"{lo:g} mm", "move": moves}]},
                              f"warm-up and hold {axis} {p_mm:g} mm")


def readout_errors(machine, axis: str, p_mm: float, resolution: str) -> dict:
    """Largest |drift| and |probe| differences [um] (X, Y, Z; the five probes) while ``axis``
    holds at ``p_mm`` (the last :data:`HOLD` minutes of :func:`hold_scenario`) against the mesh
    built at ``p_mm``, of the reference-pose mesh read at its own pose ("mesh_pose") and at the
    axis's pose ("axis_pose"); and the truth's drift at the end ("truth_drift")."""
    from dataclasses import replace

    from geometries.axes import at_pose
    from twin.io.results import to_dataset
    from twin.model import default_spec
    from twin.observe import standard_observers
    from twin.simulate import run

    a = machine.axis(axis)
    sc = hold_scenario(axis, p_mm, tuple(np.multiply(a.travel, 1e3)))
    truth = to_dataset(run(at_pose(machine, axis, p_mm * 1e-3), sc, resolution=resolution), 0, resolution)
    ref = run(machine, sc, default_spec(machine), resolution=resolution,
              observers=standard_observers(machine))
    posed = to_dataset(ref, 0, resolution)
    # the same raw readings packaged as if nothing moved: the scenario's axis standing at p_ref
    still = replace(sc, axes=())
    ctx = ref.context()
    ctx.scenario = still
    obs = {o.key: o for o in ref.observers}
    held = truth.time.values >= (WARM + 1.0) * 60.0        # arrived (a move of <= 400 mm takes < 1 min)
    out = {"truth_drift": truth.drift.values[-1]}
    for name, c in (("mesh_pose", ctx), ("axis_pose", ref.context())):
        drift = obs["drift"].change_um(obs["drift"].readings(ref.readings["drift"], c))
        probe = obs["probes"].change_um(obs["probes"].readings(ref.readings["probes"], c))
        out[name] = (np.abs(drift - truth.drift.values)[held].max(axis=0),
                     np.abs(probe - truth.probe_true.values)[held].max(axis=0))
    assert np.allclose(posed.drift.values, obs["drift"].change_um(obs["drift"].readings(ref.readings["drift"],
                                                                                       ref.context())))
    return out


def differences(ds, ref) -> dict:
    """Largest differences of ``ds`` against ``ref``: slope [um/mm], its share of ref's last slope,
    error at the last target of the last run [um], site temperatures [K] (and where), drift [um]."""
    dk = float(np.abs(ds.positioning_slope.values - ref.positioning_slope.values).max())
    dT = np.abs(ds.temperature_true.values - ref.temperature_true.values)
    return {"dk_um_per_mm": dk, "dk_share": dk / float(ref.positioning_slope.values[-1]),
            "d_error_um": float(ds.positioning_error.values[-1, -1, 0] - ref.positioning_error.values[-1, -1, 0]),
            "dT_K": float(dT.max()), "dT_site": str(ref.sensor.values[int(dT.max(axis=0).argmax())]),
            "d_drift_um": np.abs(ds.drift.values - ref.drift.values).max(axis=0)}


def poses_mm(text: str) -> list[float]:
    """argparse type of ``--poses``: comma-separated Y positions, each with its unit (``"60 mm,
    0.34 m"``; :func:`twin.units.parse_quantity`), finite and distinct; returned in mm."""
    from twin.units import UnitError, parse_quantity

    values = []
    for item in (t.strip() for t in text.split(",")):
        if not item:        # "60 mm,,340 mm": a position left out by mistake
            raise argparse.ArgumentTypeError(f"an empty position in {text!r}: write the Y positions comma-separated")
        try:
            v = 1e3 * parse_quantity(item, "length")
        except UnitError as err:
            raise argparse.ArgumentTypeError(f"expected comma-separated Y positions with their unit (e.g. "
                                             f"\"60 mm,340 mm\"): {err}") from None
        if not np.isfinite(v):
            raise argparse.ArgumentTypeError(f"{item!r} is not a finite position")
        if v in values:
            raise argparse.ArgumentTypeError(f"{v:g} mm given more than once")
        values.append(v)
    return values


def main(argv=None) -> int:
    p = cli_parser("python -m validate.studies.axis_pose", __doc__)
    p.add_argument("--quick", action="store_true", help="coarse mesh (default: the default mesh)")
    p.add_argument("--poses", type=poses_mm, default="60 mm,340 mm",
                   help="Y poses, each with its unit, to compare with the reference, within the Y travel "
                        "(default \"60 mm,340 mm\")")
    p.add_argument("--readout", action="store_true", help="only the read-out comparison (warm-up, then Y held)")
    return run_cli(p.parse_args, argv, _run)


def _run(args) -> int:
    from geometries import build_machine
    from geometries.axes import at_pose, with_feed_drives
    from twin.errors import InputError
    from twin.scenario import load_scenario

    resolution = "coarse" if args.quick else "default"
    base = with_feed_drives(build_machine("cframe-vmc"), {"Y"})
    lo, hi = (1e3 * t for t in base.axis("Y").travel)
    outside = [v for v in args.poses if not lo <= v <= hi]
    if outside:
        raise InputError("command line", "--poses", f"{outside[0]:g} mm is outside the Y axis's travel, {lo:g} to "
                                                    f"{hi:g} mm")
    sc = load_scenario(SCENARIO)
    for mm in args.poses:
        r = readout_errors(base, "Y", mm, resolution)
        print(f"read-out, {HOLD_SPEED}, Y {WARM:g} min to and fro then held at {mm:.0f} mm ({resolution}): drift X Y Z at the end on "
              f"the mesh built there {np.round(r['truth_drift'], 2)} um; largest |error| of the reference-pose mesh read "
              f"at its pose: drift {np.round(r['mesh_pose'][0], 2)}, probes {np.round(r['mesh_pose'][1], 2)} um; "
              f"read at the axis's pose: drift {np.round(r['axis_pose'][0], 2)}, probes {np.round(r['axis_pose'][1], 2)} um")
    if args.readout:
        return 0
    ref = run_at(base, sc, resolution)
    p_ref = base.axis("Y").p_ref
    print(f"{SCENARIO} on {resolution}: reference pose Y = {p_ref * 1e3:.0f} mm, k - k0 at the end "
          f"{ref.positioning_slope.values[-1]:.4f} um/mm, error at {ref.target.values[-1]:g} mm "
          f"{ref.positioning_error.values[-1, -1, 0]:.2f} um, drift {np.round(ref.drift.values[-1], 2)} um")
    for mm in args.poses:
        d = differences(run_at(at_pose(base, "Y", mm * 1e-3), sc, resolution), ref)
        print(f"pose Y = {mm:.0f} mm: |dk| <= {d['dk_um_per_mm']:.4f} um/mm ({100 * d['dk_share']:.1f} % of the end "
              f"value), error at the last target {d['d_error_um']:+.2f} um, |dT| <= {d['dT_K']:.2f} K ({d['dT_site']}), "
              f"|d drift| X Y Z <= {np.round(d['d_drift_um'], 2)} um")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
