"""How a thermal camera's frames go into the result Dataset: variables, coordinates, encodings.

Names (``suffix`` appended when a run has several cameras): ``thermogram(frame_time, v, u)``
[degC apparent], ``surface_temperature_true`` [degC], the per-pixel truth layers
``emissivity_true``, ``part_true`` (index into ``flag_meanings``; -1: the room), ``facet_true``
(mesh facet id; -1), ``depth_true`` [m], ``view_angle_true`` [deg], ``coverage_true`` (share of
the pixel's rays on the machine), and ``camera_lut(count)`` [degC] (the camera's counts to
apparent temperature with its settings); ``counts(frame_time, v, u)`` when stored.

Storage (NetCDF, zlib level 4 with byte shuffle): the thermogram as uint16 with a scale factor
just finer than the smallest step between the look-up table's values at the counts that occur,
so lut^-1 recovers every count exactly (checked here; when it cannot, the counts are stored too);
the true surface temperature as uint16 centikelvin (0.01 K); the layers as float32 / int.
"""

from __future__ import annotations

import numpy as np

UINT16_TOP = 65534  # 65535 is left free


def thermogram_encoding(lut: np.ndarray, counts: np.ndarray, chunks: tuple) -> tuple[dict, bool]:
    """(NetCDF encoding of a thermogram whose values are ``lut[counts]``, whether the counts that
    occur are recoverable exactly from the stored integers).

    The step is 0.9 of the smallest difference between consecutive look-up values over the counts
    that occur (no finer: finer integers only add incompressible bits), or the span / 65534 if
    that is coarser."""
    lo, hi = float(np.floor(lut.min())) - 1.0, float(np.ceil(lut.max())) + 1.0
    seen = np.unique(counts)
    diffs = np.diff(lut.astype(float))[seen.min():max(seen.max(), seen.min() + 1)]
    step = float(diffs[diffs > 0].min()) if np.any(diffs > 0) else (hi - lo)
    scale = np.float32(max(0.9 * step, (hi - lo) / UINT16_TOP))
    offset = np.float32(lo)
    ints = np.rint((lut.astype(np.float32) - offset) / scale)
    exact = bool(np.all(np.diff(ints[seen]) > 0))
    return {"dtype": "uint16", "scale_factor": scale, "add_offset": offset, "_FillValue": np.uint16(65535),
            **compressed(chunks)}, exact


def compressed(chunks: tuple) -> dict:
    return {"zlib": True, "complevel": 4, "shuffle": True, "chunksizes": chunks}


def camera_variables(cam, t, thermo, counts, true, lut) -> tuple[dict, dict]:
    """(data variables, coordinates) of camera ``cam`` (a :class:`twin.observe.camera.ThermalCamera`)."""
    n, view, label = cam.name, cam.view, cam.config.label
    H, W = cam.config.intrinsics.shape
    frame, pix = (n("frame_time"), n("v"), n("u")), (n("v"), n("u"))
    chunks3 = (1, H, W)
    enc_t, exact = thermogram_encoding(lut, counts, chunks3)
    store_counts = cam.config.store_counts or not exact
    cam._counts_stored = store_counts
    kelvin = {"dtype": "uint16", "scale_factor": np.float32(0.01), "add_offset": np.float32(-273.15),
              "_FillValue": np.uint16(65535), **compressed((min(len(t), 16), H, W))}
    flat = compressed((H, W))
    names = " ".join(view.part_names)
    data = {
        n("thermogram"): (frame, thermo, {"units": "degC", "long_name": f"apparent temperature, camera {label} "
                                                                       "(its object settings)", "camera": label}, enc_t),
        n("surface_temperature_true"): (frame, true, {"units": "degC", "long_name": "true surface temperature seen by "
                                                      "the pixel (mean over its rays on the machine; room air elsewhere)"},
                                        kelvin),
        n("emissivity_true"): (pix, view.emissivity.astype(np.float32), {"units": "1", "long_name": "true emissivity "
                                                                         "seen by the pixel", "nan_means": "the room"}, flat),
        n("part_true"): (pix, view.part.astype(np.int16), {"units": "1", "long_name": "part seen by the pixel's centre ray (-1: the room)",
                                                           "flag_values": np.arange(len(view.part_names), dtype=np.int16),
                                                           "flag_meanings": names}, flat),
        n("facet_true"): (pix, view.facet.astype(np.int32), {"units": "1", "long_name": "mesh facet hit by the pixel's centre ray "
                                                             "(-1: the room)"}, flat),
        n("depth_true"): (pix, view.depth.astype(np.float32), {"units": "m", "long_name": "distance along the centre "
                                                               "ray to the surface", "nan_means": "the room"}, flat),
        n("view_angle_true"): (pix, view.view_angle.astype(np.float32), {"units": "deg", "long_name": "angle between "
                                                                         "the centre ray and the surface normal",
                                                                         "nan_means": "the room"}, flat),
        n("coverage_true"): (pix, view.coverage.astype(np.float32), {"units": "1", "long_name": "share of the "
                                                                     "pixel's footprint on the machine"}, flat),
        n("camera_lut"): ((n("count"),), lut.astype(np.float32), {"units": "degC", "long_name": "apparent temperature "
                                                                   "of each 14-bit count with the camera's settings"}),
    }
    if store_counts:
        data[n("counts")] = (frame, counts, {"units": "1", "long_name": "detector counts (ADC)"}, compressed(chunks3))
    coords = {
        n("frame_time"): (n("frame_time"), t, {"units": "s", "long_name": f"frame time, camera {label}"}),
        n("v"): (n("v"), np.arange(H), {"units": "1", "long_name": "pixel row, top to bottom"}),
        n("u"): (n("u"), np.arange(W), {"units": "1", "long_name": "pixel column, left to right"}),
        n("count"): (n("count"), np.arange(len(lut)), {"units": "1", "long_name": "detector count"}),
    }
    return data, coords
