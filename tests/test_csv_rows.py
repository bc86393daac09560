"""CSV data files (twin.io.csv_rows): every reader names the line an editor shows, blank lines
counted, and reads a number only as a data file writes one (ASCII digits; not 2_0, not
Arabic-Indic or full-width digits, which Python's float() and int() accept)."""

from __future__ import annotations

import pytest

from tests.fuzz_files import MAPPING, measurement_csv
from twin.errors import InputError
from twin.io.csv_rows import cell_number, data_rows

ODD = ["2_0", "٢٠", "２0", "0x14", "20,", "1e", "--2", ""]


def test_rows_keep_their_line_numbers_and_numbers_are_plain():
    lines, rows = data_rows("a,b\n\n1,2\n , \n\"3\n\",4\n5,6\n")
    assert lines == [1, 3, 6, 7] and rows[2] == ["3\n", "4"]
    for text, value in (("20", 20.0), (" -1.5e3 ", -1500.0), (".5", 0.5), ("7.", 7.0), ("+2", 2.0)):
        assert cell_number(text) == value
    assert [str(cell_number(t)) for t in ("nan", "-Inf", "infinity")] == ["nan", "-inf", "inf"]
    for text in ODD:
        with pytest.raises(ValueError):
            cell_number(text)


def _error(call) -> InputError:
    with pytest.raises(InputError) as err:
        call()
    return err.value


def test_a_room_record_names_the_line_and_refuses_odd_digits(tmp_path):
    from twin.io.room_csv import read_room_csv
    path = tmp_path / "room.csv"
    path.write_text("time [h],air [degC]\n0,20\n\n\n1,21\n\n2,abc\n", encoding="utf-8")
    err = _error(lambda: read_room_csv(path))
    assert (err.field, err.message) == ("air", "line 7: 'abc' is not a number")
    path.write_text("time [h],air [degC]\n0,20\n\n1,21,3\n", encoding="utf-8")
    assert _error(lambda: read_room_csv(path)).field == "line 4"
    for odd in ODD[:3]:
        path.write_text(f"time [h],air [degC]\n0,20\n1,{odd}\n2,21\n", encoding="utf-8")
        err = _error(lambda: read_room_csv(path))
        assert (err.field, err.message) == ("air", f"line 3: {odd!r} is not a number")


def test_a_measurement_names_the_line_and_refuses_odd_digits(tmp_path):
    from twin.io.measurement import read_measurement
    lines = measurement_csv().splitlines()
    (tmp_path / "m.toml").write_text(MAPPING, encoding="utf-8")
    blank = lines[:3] + ["", ""] + lines[3:]          # two blank lines before the third data row
    cells = blank[5].split(",")
    for cell, message in (("2_0", "line 6: '2_0' is not a number"), ("٢٠", "line 6: '٢٠' is not a number"),
                          ("", "1 missing/NaN value(s), first at line 6"), ("inf", "line 6: not finite (inf)")):
        edited = blank[:5] + [",".join(cells[:-1] + [cell])] + blank[6:]
        (tmp_path / "m.csv").write_text("\n".join(edited) + "\n", encoding="utf-8")
        err = _error(lambda: read_measurement(tmp_path / "m.csv"))
        assert (err.field, err.message) == (edited[0].split(",")[-1], message)
    short = blank[:5] + [",".join(cells[:-1])] + blank[6:]
    (tmp_path / "m.csv").write_text("\n".join(short) + "\n", encoding="utf-8")
    assert _error(lambda: read_measurement(tmp_path / "m.csv")).field == "line 6"


def test_a_value_beyond_its_limit_is_named_by_its_line(tmp_path):
    """A number that parses but breaks a physical limit is named by the line an editor shows
    (blank lines counted), as a syntax error is: the limits said "value #6" for line 7."""
    from twin.io.measurement import read_measurement
    from twin.io.room_csv import read_room_csv

    lines = measurement_csv().splitlines()
    (tmp_path / "m.toml").write_text(MAPPING, encoding="utf-8")
    blank = lines[:3] + [""] + lines[3:]          # a blank line before the third data row: it is line 5
    cells = blank[4].split(",")
    speed = blank[0].split(",").index("spindle_rpm")
    cells[speed] = "12000"                        # beyond the C-frame's 9000 rpm (and a log's margin)
    (tmp_path / "m.csv").write_text("\n".join(blank[:4] + [",".join(cells)] + blank[5:]) + "\n", encoding="utf-8")
    err = _error(lambda: read_measurement(tmp_path / "m.csv"))
    assert err.field == "spindle_rpm" and err.message.startswith("line 5: 12000 rpm is beyond"), err.message
    path = tmp_path / "room.csv"
    path.write_text("time [h],air [degC]\n0,20\n\n1,21\n2,-300\n", encoding="utf-8")
    err = _error(lambda: read_room_csv(path))
    assert err.field == "air" and err.message.startswith("line 5: -300 degC is below absolute zero"), err.message


def test_a_learners_table_names_the_line_refuses_odd_digits_and_unnamed_columns(tmp_path):
    from learners.table import load_table
    path = tmp_path / "run.csv"
    path.write_text("time,T1,dz\n0,20,0\n\n\n60,21,1\n120,22,nan\n", encoding="utf-8")
    err = _error(lambda: load_table(str(path), "dz"))
    assert (err.field, err.message) == ("dz", "line 6: NaN value")
    path.write_text("time,T1,dz\n0,20,0\n60,２1,1\n120,22,2\n", encoding="utf-8")
    err = _error(lambda: load_table(str(path), "dz"))
    assert err.field == "T1" and "line 3" in err.message
    path.write_text("time,,dz\n0,20,0\n60,21,1\n120,22,2\n", encoding="utf-8")
    err = _error(lambda: load_table(str(path), "dz"))
    assert (err.field, err.message) == ("header", "column 2 has no name; name every column")


def test_a_schedule_table_names_the_line(tmp_path):
    from geometries import build_machine
    from twin.effects.custom import effects_from_dict
    (tmp_path / "f.csv").write_text("time,factor\n0,1\n\n1,2_0\n", encoding="utf-8")
    spec = {"effects": {"lamp": {"kind": "heat_source", "region": "saddle", "power": "10 W", "schedule": "table",
                                 "table": {"file": "f.csv", "time_unit": "h"}}}}
    err = _error(lambda: effects_from_dict(spec, "e.toml", build_machine("cframe-vmc"), tmp_path))
    assert (err.field, err.message) == ("factor", "line 4: '2_0' is not a number")


@pytest.mark.parametrize("speed", ["٩٠٠٠ rpm", "９０００ rpm", "9_000 rpm"])
def test_a_scenario_quantity_in_other_digits_is_refused(speed):
    from twin.scenario import scenario_from_dict
    data = {"sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
            "spindle": [{"speed": speed, "duration": "10 min"}]}
    err = _error(lambda: scenario_from_dict(data, "s.toml"))
    assert err.field == "spindle[0].speed" and "is not a decimal number" in err.message
