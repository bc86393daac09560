"""``twin report iso230-3 RESULT [--test etve|spindle|axis] [--segment DURATION] -o DIR``: the ISO
230-3 evaluation of a twin result or a measurement (:mod:`validate.iso230`), written as
``DIR/index.html`` (figures embedded) and ``DIR/report.md``; registered with ``twin`` through the
``thermal_twin.commands`` entry point."""

from __future__ import annotations

from twin.cli.options import positive_quantity_value
from twin.io.atomic import output_folder
from twin.io.paths import Files
from validate.inputs import declare_inputs

REPORT_FILES = ("index.html", "report.md")


def add_report_parser(subparsers) -> None:
    p = subparsers.add_parser("report", help="standard evaluations of a result or measurement: "
                                             "'iso230-3' (ETVE, spindle or axis thermal drift)")
    p.add_argument("kind", choices=["iso230-3"], help="the evaluation: iso230-3 (ISO 230-3 thermal effects)")
    p.add_argument("measurement", metavar="RESULT",
                   help="a twin NetCDF result, or a measurement CSV with its TOML column mapping")
    p.add_argument("--mapping", help="TOML column mapping of a CSV (default: the CSV's name with .toml)")
    p.add_argument("--test", choices=["etve", "spindle", "axis"],
                   help="which ISO 230-3 test (default: axis with positioning errors or moved axes, spindle when "
                        "the spindle or the C axis turned, else etve)")
    p.add_argument("--segment", help="length of the segments of the statistics, e.g. '6 h' (default: 24 h for "
                                     "etve, 1 h otherwise)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (index.html, report.md)")
    p.set_defaults(func=run_report, scenario=None)


def run_report(args) -> int:
    from twin.io.measurement import read_measurement
    from validate.iso230 import default_test, evaluate
    from validate.iso230_report import write_iso230_report

    segment = None if args.segment is None else positive_quantity_value(args.segment, "time", "--segment")
    files = Files()
    declare_inputs(files, args)
    out = files.folder(args.output, "-o", REPORT_FILES)
    ds = read_measurement(args.measurement, args.mapping)
    test = args.test or default_test(ds)
    ev = evaluate(ds, test, segment, source=str(args.measurement))
    with output_folder(out):
        md, index = write_iso230_report(ev, out)
    print(f"ISO 230-3 {test}: " + ", ".join(f"{c.name} {c.range:.1f} {c.unit}" for c in ev.channels)
          + (f"; room air range{' at the runs' if test == 'axis' else ''} {ev.air_range:.1f} K"
             if ev.air is not None else ""))
    for d in ev.departures:
        print(f"  not as the test asks: {d}")
    print(f"wrote {index} and {md}")
    return 0
