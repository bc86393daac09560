"""``twin frames`` and ``twin simulate --field/--camera``: bad input and bad outputs are one line
``error: FILE: FIELD: message`` with exit code 2 and nothing written; an output never replaces an
input; an XDMF field comes with a deterministic companion ``.h5``; the help says what is done.

One camera run on the coarse mesh (10 min at one sample a minute: 11 frames) is built once for
the module, with its XDMF field; every test works on copies in its own folder.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from twin.cli import main

SCENARIO = """name = "s"
sample_interval = "60 s"
[ambient]
temperature = "20 degC"
[[spindle]]
speed = "6000 rpm"
duration = "10 min"
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The folder of one camera run: s.toml, x.nc (camera carrier-front), hot.xdmf + hot.h5."""
    folder = tmp_path_factory.mktemp("camera-run")
    (folder / "s.toml").write_text(SCENARIO)
    assert main(["simulate", "cframe-vmc", str(folder / "s.toml"), "-o", str(folder / "x.nc"), "--mesh", "coarse",
                 "--camera", "carrier-front", "--field", str(folder / "hot.xdmf")]) == 0
    return folder


@pytest.fixture
def work(run, tmp_path, monkeypatch):
    """A fresh folder (the current one) holding copies of the run's s.toml and x.nc."""
    for name in ("s.toml", "x.nc"):
        shutil.copy(run / name, tmp_path / name)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _error(capsys, argv) -> str:
    """The one-line error of ``twin argv`` (exit code 2, no traceback)."""
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and "Traceback" not in err, err
    return err


def _tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (hidden ones too) with its bytes; folders as None."""
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None) for p in sorted(folder.rglob("*"))}


def _files(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


# ---------------------------------------------------------------------------------- the output
@pytest.mark.parametrize("output", ["x.nc", "s.toml", "/dev/null"])
def test_an_output_that_is_a_file_or_the_input_is_refused(capsys, work, output):
    """``-o`` naming the result itself, another file or a device is one error naming ``-o``
    (the result: "never replaces an input"); every file is unchanged, nothing is added."""
    before = _tree(work)
    err = _error(capsys, ["frames", "x.nc", "-o", output])
    assert err.startswith(f"error: {output}: -o: ")
    if output == "x.nc":
        assert "never replaces an input" in err
    assert _tree(work) == before


def test_a_file_in_the_way_of_a_subfolder_is_refused_before_any_frame(capsys, work):
    """``fr/png`` a file: the export needs a folder there; refused before the TIFFs are written
    (the audit found 22 TIFF/JSON files, then a traceback)."""
    (work / "fr").mkdir()
    (work / "fr" / "png").write_text("x\n")
    err = _error(capsys, ["frames", "x.nc", "-o", "fr"])
    assert "-o" in err and "fr/png" in err
    assert _files(work / "fr") == ["png"] and (work / "fr" / "png").read_text() == "x\n"


def test_a_missing_parent_folder_is_refused(capsys, work):
    """``-o a/b/c`` with no ``a``: refused like ``report``/``demo``/``dataset`` do, no folder made."""
    err = _error(capsys, ["frames", "x.nc", "-o", "a/b/c"])
    assert err.startswith("error: a/b/c: -o: ") and "does not exist" in err
    assert not (work / "a").exists()


def test_a_frame_file_is_never_the_input(capsys, work):
    """The result lying where a frame would go (``fr/png/frame_00004.png``, not the first frame
    of its kind): refused, the result untouched, nothing written."""
    (work / "fr" / "png").mkdir(parents=True)
    inside = work / "fr" / "png" / "frame_00004.png"
    shutil.copy(work / "x.nc", inside)
    before = _tree(work)
    err = _error(capsys, ["frames", str(inside), "-o", "fr"])
    assert "never replaces an input" in err and "frame_00004.png" in err
    assert _tree(work) == before


def test_a_camera_folder_in_the_way_is_refused(capsys, work):
    """Two cameras go to ``DIR/NAME/``; a file ``DIR/NAME`` is refused before anything is written."""
    ds = xr.load_dataset(work / "x.nc")
    info = json.loads(ds.attrs["camera"])
    ds["thermogram_b"] = ds.thermogram.rename(frame_time="frame_time_b")
    ds.attrs["camera_b"] = json.dumps({**info, "name": "b", "suffix": "_b"})
    ds.to_netcdf(work / "two.nc")
    (work / "fr").mkdir()
    (work / "fr" / "b").write_text("x\n")
    err = _error(capsys, ["frames", "two.nc", "-o", "fr", "--png"])
    assert err.startswith(f"error: {Path('fr') / 'b'}: -o: ")
    assert _files(work / "fr") == ["b"]


def test_the_export_writes_the_declared_files_and_nothing_else(capsys, work):
    """A good export: the files :func:`export_files` names (what is declared) are exactly the
    files written, no temporary file is left; a rerun into the same folder works."""
    from twin.io.thermography import KINDS, export_files

    assert main(["frames", "x.nc", "-o", "fr"]) == 0
    assert _files(work / "fr") == sorted(export_files(11, 1, KINDS, "carrier-front"))
    assert main(["frames", "x.nc", "-o", "fr"]) == 0              # a rerun
    assert main(["frames", "x.nc", "-o", "fr4", "--every", "4", "--png"]) == 0
    assert "wrote 3 PNG frames" in capsys.readouterr().out
    assert _files(work / "fr4") == sorted(export_files(11, 4, ("png",), "carrier-front"))
    assert not [p for p in work.rglob(".twin-*")]


# ---------------------------------------------------------------------------------- the input
def test_a_malformed_camera_attribute_is_one_error(capsys, work):
    """A ``camera`` attribute that is not JSON: ``error: y.nc: camera: ...``, no output folder."""
    ds = xr.load_dataset(work / "x.nc")
    ds.attrs["camera"] = "{bad"
    ds.to_netcdf(work / "y.nc")
    err = _error(capsys, ["frames", "y.nc", "-o", "fr2"])
    assert err.startswith("error: y.nc: camera: ") and "JSON" in err
    assert not (work / "fr2").exists()


def test_two_cameras_of_one_name_are_refused(capsys, work):
    """Two camera attributes naming the same camera (an edited file): the second's frames would
    replace the first's in one folder; one error, no output folder."""
    ds = xr.load_dataset(work / "x.nc")
    ds.attrs["camera_again"] = ds.attrs["camera"]
    ds.to_netcdf(work / "two.nc")
    err = _error(capsys, ["frames", "two.nc", "-o", "fr6"])
    assert err.startswith("error: two.nc: camera_again: a second camera named ") and "replace" in err
    assert not (work / "fr6").exists()


def test_a_nan_pixel_is_refused_with_its_frame_time(capsys, work):
    """A NaN pixel in frame 3 (t = 180 s) is refused naming the file, ``thermogram`` and the
    time; no folder, no PNG is written."""
    ds = xr.load_dataset(work / "x.nc")
    ds["thermogram"].values[3, 5, 5] = np.nan
    ds.to_netcdf(work / "nan.nc")
    err = _error(capsys, ["frames", "nan.nc", "-o", "fr3"])
    assert err.startswith("error: nan.nc: thermogram: ") and "t = 180 s" in err
    assert not (work / "fr3").exists()


@pytest.mark.parametrize("var,unit", [("thermogram", "K"), ("frame_time", "min")])
def test_a_camera_variable_in_another_unit_is_refused(capsys, work, var, unit):
    """A thermogram in K (exported as degC it was 273 K too warm) or frame times in minutes (the
    sidecars said seconds): ``error: u.nc: VAR: in 'UNIT'``, no output folder."""
    ds = xr.load_dataset(work / "x.nc")
    ds[var].attrs["units"] = unit
    if var == "frame_time":          # xarray decodes a time unit it knows; keep the number as written
        ds[var].encoding.pop("units", None)
    ds.to_netcdf(work / "u.nc")
    err = _error(capsys, ["frames", "u.nc", "-o", "fr5", "--tiff"])
    assert err.startswith(f"error: u.nc: {var}: in '{unit}'"), err
    assert not (work / "fr5").exists()


def test_an_input_that_is_not_a_netcdf_result_or_is_a_folder(capsys, work):
    """A scenario as the result: one short line (no xarray URLs); a folder: "is a directory"."""
    err = _error(capsys, ["frames", "s.toml", "-o", "f"])
    assert err == "error: s.toml: result: not a NetCDF result file"
    (work / "d").mkdir()
    err = _error(capsys, ["frames", "d", "-o", "f"])
    assert err.startswith("error: d: result: ") and "directory" in err
    assert not (work / "f").exists()


# --------------------------------------------------------------------------- simulate --field
def test_an_xdmf_field_has_a_deterministic_companion_h5(capsys, run):
    """``--field hot.xdmf`` writes ``hot.h5`` beside it, named in the XDMF; a rerun gives
    byte-identical files and leaves no hidden temporary file (the audit found a new
    ``.twin-XXXXXXXX.h5`` per run, referenced by the XDMF)."""
    import meshio

    assert 'hot.h5:/' in (run / "hot.xdmf").read_text() and ".twin-" not in (run / "hot.xdmf").read_text()
    before = {name: (run / name).read_bytes() for name in ("hot.xdmf", "hot.h5")}
    assert main(["simulate", "cframe-vmc", str(run / "s.toml"), "-o", str(run / "x2.nc"), "--mesh", "coarse",
                 "--field", str(run / "hot.xdmf")]) == 0
    assert "hot.h5" in capsys.readouterr().out
    assert {name: (run / name).read_bytes() for name in before} == before
    assert sorted(p.name for p in run.iterdir()) == ["hot.h5", "hot.xdmf", "s.toml", "x.nc", "x2.nc"]
    with meshio.xdmf.TimeSeriesReader(run / "hot.xdmf") as series:   # one step, at the field's instant [s]
        series.read_points_cells()
        assert series.num_steps == 1
        t, point_data, _ = series.read_data(0)
    assert np.all(np.isfinite(point_data["temperature_degC"])) and 0.0 <= t <= 3600.0


def test_the_companion_h5_never_replaces_an_input(capsys, work):
    """A scenario named ``hot.h5`` and ``--field hot.xdmf``: refused before the run (the h5
    would replace the scenario), the scenario unchanged, nothing written."""
    shutil.copy(work / "s.toml", work / "hot.h5")
    before = _tree(work)
    err = _error(capsys, ["simulate", "cframe-vmc", "hot.h5", "-o", "r.nc", "--mesh", "coarse",
                          "--field", "hot.xdmf"])
    assert err.startswith("error: hot.h5: --field: ") and "never replaces an input" in err
    assert _tree(work) == before


def test_the_help_says_when_frames_are_taken_and_names_the_companion(capsys):
    """``--camera``: a frame at every sample (or a scenario camera's frame_interval), not "every
    10 s"; ``--field``: the .xdmf's companion .h5."""
    assert main(["simulate", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    camera = text.split("--camera NAME[,NAME]", 2)[-1].split("--effects", 1)[0]
    assert "every 10 s" not in camera and "every sample" in camera and "frame_interval" in camera
    field = text.split("--field FILE", 2)[-1].split("--camera", 1)[0]
    assert ".h5" in field


def test_an_export_never_mixes_with_an_earlier_one(capsys, work):
    """Frames of an earlier export that this one would not replace (another --every, kind or
    camera into the same folder: the README's two commands once left 241 PNGs of two cameras,
    named alike) are refused before anything is written; the same export again is a rerun."""
    assert main(["frames", "x.nc", "-o", "fr", "--png", "--every", "2"]) == 0
    capsys.readouterr()
    before = _tree(work)
    err = _error(capsys, ["frames", "x.nc", "-o", "fr", "--png", "--every", "3"])
    assert "frame_00002.png" in err and "would mix" in err
    err = _error(capsys, ["frames", "x.nc", "-o", "fr", "--gif"])
    assert "frame_00000.png" in err
    assert _tree(work) == before
    assert main(["frames", "x.nc", "-o", "fr", "--png", "--every", "2"]) == 0
    assert sorted(_tree(work)) == sorted(before)


def test_an_export_of_another_camera_is_not_replaced_file_for_file(capsys, work):
    """Two single-camera exports of the same length into one folder would name their files alike:
    the second would replace the first silently. Each export names its camera (the TIFFs' JSON
    sidecars, a text chunk in each PNG), so another camera's export is refused before anything is
    written; the same camera again is a rerun."""
    from twin.io.thermography import exported_camera

    with xr.open_dataset("x.nc") as ds:
        other = ds.load()
    info = json.loads(other.attrs["camera"])
    other.attrs["camera"] = json.dumps({**info, "name": "other-camera"})
    other.to_netcdf("y.nc", engine="h5netcdf")
    for kind, first in (("--png", "fr/png/frame_00000.png"), ("--tiff", "fr/tiff/frame_00000.json")):
        assert main(["frames", "x.nc", "-o", "fr", kind]) == 0
        capsys.readouterr()
        assert exported_camera(first) == info["name"]
        before = _tree(work)
        err = _error(capsys, ["frames", "y.nc", "-o", "fr", kind])
        assert first in err and f"export of camera {info['name']!r}" in err and "'other-camera'" in err
        assert _tree(work) == before
        assert main(["frames", "x.nc", "-o", "fr", kind]) == 0
        shutil.rmtree("fr")


def test_a_cameras_counts_from_python_name_the_suffix_of_each_camera(work):
    """``camera_counts(ds)`` on a result of several cameras (variables ``thermogram_<name>``, no
    camera at the suffix ``""``) is one InputError on ``suffix`` listing each camera and its
    suffix, not a KeyError; with the suffix it gives that camera's counts, the same as a
    one-camera result's."""
    from twin.errors import InputError
    from twin.io.thermography import camera_counts

    with xr.open_dataset("x.nc") as ds:
        one = ds.load()
    info = json.loads(one.attrs["camera"])
    camera_vars = [v for v in one.data_vars if "frame_time" in one[v].dims] + ["camera_lut", "frame_time"]
    several = one.rename({v: f"{v}_carrier_front" for v in camera_vars})
    del several.attrs["camera"]
    several.attrs["camera_carrier_front"] = json.dumps({**info, "suffix": "_carrier_front"})
    with pytest.raises(InputError) as err:
        camera_counts(several)
    assert err.value.field == "suffix" and "carrier-front (suffix '_carrier_front')" in str(err.value)
    assert np.array_equal(camera_counts(several, "_carrier_front"), camera_counts(one))
