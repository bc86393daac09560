"""Bad logged axis motion for the fuzz suite (:mod:`tests.fuzz_cases`): the good measurement CSV
with an axis column (``axis_position`` or ``axis_feed``) whose mapping or values are bad."""

from __future__ import annotations

import numpy as np

from tests.fuzz_files import MAPPING, measurement_csv


# logged axis positions (role axis_position): a good CSV column y_mm with a bad mapping or values
YPOS = '[columns.y_mm]\nrole = "axis_position"\naxis = "Y"\nunit = "mm"\n'


def _ypos(value):
    def edit(cols):
        cols["y_mm"] = np.where(np.arange(len(cols["t_s"])) == 5, value, 140.0)
    return measurement_csv(edit)


# logged axis feeds (role axis_feed): a CSV column y_feed, integrated from the mapping's start
YFEED = '[columns.y_feed]\nrole = "axis_feed"\naxis = "Y"\nstart = "140 mm"\nunit = "mm/s"\n'


def _yfeed(value):
    def edit(cols):
        cols["y_feed"] = np.full(len(cols["t_s"]), value)
    return measurement_csv(edit)


def _yfeed_alternating(value):
    """+value, -value, ... [mm/s]: the trapezoidal positions stay at the start, the feed is too fast."""
    def edit(cols):
        cols["y_feed"] = value * (1 - 2 * (np.arange(len(cols["t_s"])) % 2))
    return measurement_csv(edit)


def _ypos_alternating(step):
    """140 mm, 140 + step, 140, ...: with the times read in ms, ``step`` mm every 60 ms."""
    def edit(cols):
        cols["y_mm"] = 140.0 + step * (np.arange(len(cols["t_s"])) % 2)
    return measurement_csv(edit)


def _yboth(cols):
    cols["y_mm"], cols["y_feed"] = np.full(len(cols["t_s"]), 140.0), np.zeros(len(cols["t_s"]))


# (id, CSV text, mapping text, source file, field)
AXIS_LOG_EDITS = [
    ("axis-feed-no-start", _yfeed(0.0), MAPPING + YFEED.replace('start = "140 mm"\n', ''), "m.toml",
     "columns.y_feed.start"),
    ("axis-feed-start-no-unit", _yfeed(0.0), MAPPING + YFEED.replace('"140 mm"', '"140"'), "m.toml",
     "columns.y_feed.start"),
    ("axis-feed-wrong-unit", _yfeed(0.0), MAPPING + YFEED.replace('"mm/s"', '"mm"'), "m.toml", "columns.y_feed.unit"),
    ("axis-feed-leaves-travel", _yfeed(1.0), MAPPING + YFEED, "m.csv", "y_feed"),
    ("axis-feed-and-position", measurement_csv(_yboth), MAPPING + YPOS + YFEED, "m.toml", "columns.y_feed.axis"),
    ("axis-feed-unknown-key", _yfeed(0.0), MAPPING + YFEED.replace('axis = "Y"', 'axis = "Y"\nstop = "0 mm"'),
     "m.toml", "columns.y_feed.stop"),
    ("axis-position-unknown-axis", _ypos(140.0), MAPPING + YPOS.replace('"Y"', '"W"'), "m.toml", "columns.y_mm.axis"),
    ("axis-position-no-axis", _ypos(140.0), MAPPING + YPOS.replace('axis = "Y"\n', ''), "m.toml",
     "columns.y_mm.axis"),
    ("axis-position-outside-travel", _ypos(900.0), MAPPING + YPOS, "m.csv", "y_mm"),
    ("axis-feed-too-fast", _yfeed_alternating(3000.0), MAPPING + YFEED, "m.csv", "y_feed"),
    ("axis-position-too-fast", _ypos_alternating(200.0), MAPPING.replace('role = "time"\nunit = "s"',
                                                                         'role = "time"\nunit = "ms"') + YPOS,
     "m.csv", "y_mm"),
    ("axis-position-wrong-unit", _ypos(140.0), MAPPING + YPOS.replace('"mm"', '"mm/s"'), "m.toml",
     "columns.y_mm.unit"),
]
