"""``twin list machines | scenarios | effects | instruments``."""

from __future__ import annotations


def add_parser(sub) -> None:
    p = sub.add_parser("list", help="list machines, scenarios, effects or instruments")
    p.add_argument("what", choices=["machines", "scenarios", "effects", "instruments"])
    p.set_defaults(func=run)


def run(args) -> int:
    from geometries import MACHINES, build_machine
    from twin.effects import DEFAULT_EFFECTS, EFFECTS
    from twin.observe.instruments import INSTRUMENTS
    from twin.scenario import available, load_scenario

    if args.what == "machines":
        for name in sorted(MACHINES):
            m = build_machine(name)
            print(f"{name}: {m.description}\n  parts: {', '.join(p.name for p in m.parts)}\n"
                  f"  mesh resolutions: {', '.join(f'{k} ({v * 1e3:g} mm)' for k, v in m.resolutions.items())}")
    elif args.what == "scenarios":
        for name in available():
            sc = load_scenario(name)
            print(f"{name}: {sc.duration / 60:g} min, sample interval {sc.sample_interval:g} s\n  {sc.description}")
    elif args.what == "effects":
        for name in sorted(EFFECTS):
            e = EFFECTS[name]
            tag = " (default)" if name in DEFAULT_EFFECTS else ""
            print(f"{name}{tag}: {e.summary}\n  reference: {e.reference}")
            for p in e.parameters:
                print(f"    {p.describe()}")
    else:
        for name, params in INSTRUMENTS.items():
            print(name)
            for p in params:
                print(f"    {p.describe()}")
    return 0
