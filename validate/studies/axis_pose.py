"""What the single reference pose costs: ``seed003-exp1`` on meshes built with the Y axis at the
ends of its stroke against the mesh at the reference pose.

``python -m validate.studies.axis_pose [--quick] [--poses 60,340]`` runs ``cframe-vmc`` with its
feed drive on ``seed003-exp1`` three times, the saddle and table built at Y = p_ref (200 mm) and at
each pose of ``--poses`` [mm] (:func:`geometries.axes.at_pose`), and prints per pose the largest
change of the thermal slope k - k0 [um/mm], of the error at the last target [um], of the sites'
temperatures [K] and of the tool-point drift [um].
"""

from __future__ import annotations

import argparse

import numpy as np

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


def differences(ds, ref) -> dict:
    """Largest differences of ``ds`` against ``ref``: slope [um/mm], its share of ref's last slope,
    error at the last target of the last run [um], site temperatures [K] (and where), drift [um]."""
    dk = float(np.abs(ds.positioning_slope.values - ref.positioning_slope.values).max())
    dT = np.abs(ds.temperature_true.values - ref.temperature_true.values)
    return {"dk_um_per_mm": dk, "dk_share": dk / float(ref.positioning_slope.values[-1]),
            "d_error_um": float(ds.positioning_error.values[-1, -1, 0] - ref.positioning_error.values[-1, -1, 0]),
            "dT_K": float(dT.max()), "dT_site": str(ref.sensor.values[int(dT.max(axis=0).argmax())]),
            "d_drift_um": np.abs(ds.drift.values - ref.drift.values).max(axis=0)}


def main(argv=None) -> int:
    from geometries import build_machine
    from geometries.axes import at_pose, with_feed_drives
    from twin.scenario import load_scenario

    p = argparse.ArgumentParser(prog="python -m validate.studies.axis_pose", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="coarse mesh (default: the default mesh)")
    p.add_argument("--poses", default="60,340", help="Y poses [mm] to compare with the reference (default 60,340)")
    args = p.parse_args(argv)
    resolution = "coarse" if args.quick else "default"
    sc = load_scenario(SCENARIO)
    base = with_feed_drives(build_machine("cframe-vmc"))
    ref = run_at(base, sc, resolution)
    p_ref = base.axis("Y").p_ref
    print(f"{SCENARIO} on {resolution}: reference pose Y = {p_ref * 1e3:.0f} mm, k - k0 at the end "
          f"{ref.positioning_slope.values[-1]:.4f} um/mm, error at {ref.target.values[-1]:g} mm "
          f"{ref.positioning_error.values[-1, -1, 0]:.2f} um, drift {np.round(ref.drift.values[-1], 2)} um")
    for mm in (float(v) for v in args.poses.split(",")):
        d = differences(run_at(at_pose(base, "Y", mm * 1e-3), sc, resolution), ref)
        print(f"pose Y = {mm:.0f} mm: |dk| <= {d['dk_um_per_mm']:.4f} um/mm ({100 * d['dk_share']:.1f} % of the end "
              f"value), error at the last target {d['d_error_um']:+.2f} um, |dT| <= {d['dT_K']:.2f} K ({d['dT_site']}), "
              f"|d drift| X Y Z <= {np.round(d['d_drift_um'], 2)} um")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
