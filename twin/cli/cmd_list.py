"""``twin list machines | scenarios | effects [--machine M] | instruments``."""

from __future__ import annotations


def add_parser(sub) -> None:
    p = sub.add_parser("list", help="list machines, scenarios, effects or instruments")
    p.add_argument("what", choices=["machines", "scenarios", "effects", "instruments"])
    p.add_argument("--machine", help="with 'effects': only the effects that apply to this machine, "
                                     "its defaults marked")
    p.set_defaults(func=run)


def _one_line(text: str) -> str:
    """A description written over several lines of its TOML or docstring as one line, so that every
    line of the listing that is not indented starts a new entry."""
    return " ".join(text.split())


def _machines() -> None:
    from geometries import MACHINES, build_machine
    from twin import limits

    for name in sorted(MACHINES):
        m = build_machine(name)
        print(f"{name}: {_one_line(m.description)}\n  parts: {', '.join(p.name for p in m.parts)}\n"
              f"  maximum spindle speed: {limits.max_speed(m):g} rpm\n"
              f"  mesh resolutions: {', '.join(f'{k} ({v * 1e3:g} mm)' for k, v in m.resolutions.items())}\n"
              f"  default effects: {', '.join(m.default_effects)}\n  roles: {', '.join(m.roles)}\n"
              f"  camera poses: {', '.join([p.name for p in m.camera_poses] + ['overview-front'])}")


def _effects(machine_name: str | None) -> None:
    from geometries import MACHINES, build_machine
    from geometries.axes import with_feed_drives
    from twin.api import machine_by_name
    from twin.effects import EFFECTS
    from twin.model import uncertain_range
    from twin.units import format_quantity

    def show(name, tag, where="", machine=None):
        """One effect; with ``machine``, at that machine's own defaults and uncertain ranges."""
        e = EFFECTS[name]
        own = machine.effect_defaults.get(name) if machine is not None else None
        print(f"{name}{tag}: {_one_line(e.summary)}\n  reference: {e.reference}{where}")
        for p in e.parameters:
            print(f"    {p.describe((own or {}).get(p.name))}")
        for u in e.uncertain:
            dim = e.parameter(u.name).dimension
            lo, hi = uncertain_range(machine, name, u)
            print(f"    uncertain {u.name}: {format_quantity(lo, dim)} .. {format_quantity(hi, dim)} "
                  f"({'linear' if u.linear else 'nonlinear'}): {u.why}")

    def qualifier(name, base, m):
        """None if ``name`` is not on by default on machine ``m`` (``base`` with its feed drives),
        "" if it always is, " when a scenario moves its Z axis" (the axes whose feed drives bring
        it) otherwise."""
        if name in base.default_effects:
            return ""
        if name not in m.default_effects:
            return None
        axes = [a.name for a in base.axes if name in with_feed_drives(base, {a.name}).default_effects]
        return f" when a scenario moves its {' or '.join(axes)} axis" if axes else " when a scenario moves an axis"

    if machine_name is None:
        # a machine with a feed drive offers its effects when a scenario moves an axis
        bases = [build_machine(n) for n in sorted(MACHINES)]
        machines = [with_feed_drives(b) for b in bases]
        for name in sorted(EFFECTS):
            on = [m.name for m in machines if EFFECTS[name].applies_to(m)]
            default = [m.name + q for b, m in zip(bases, machines) if (q := qualifier(name, b, m)) is not None]
            show(name, f" (default on {', '.join(default)})" if default else "",
                 f"\n  applies to: {', '.join(on) or 'no bundled machine'}")
        return
    base = machine_by_name(machine_name, "--machine")
    m = with_feed_drives(base)
    refused = []
    for name in sorted(EFFECTS):
        missing = EFFECTS[name].missing_roles(m)
        if missing:
            refused.append(f"{name} (needs {missing[0]})")
        else:
            q = qualifier(name, base, m)
            show(name, "" if q is None else f" (default{q})", machine=m)
    if refused:
        print(f"not applicable to {m.name}: {', '.join(refused)}")


def run(args) -> int:
    from twin.errors import InputError
    from twin.observe.instruments import INSTRUMENTS
    from twin.scenario import available, load_scenario

    if args.machine and args.what != "effects":
        raise InputError("command line", "--machine", "only 'twin list effects' takes --machine")
    if args.what == "machines":
        _machines()
    elif args.what == "scenarios":
        for name in available():
            sc = load_scenario(name)
            print(f"{name}: {sc.duration / 60:g} min, sample interval {sc.sample_interval:g} s\n  {_one_line(sc.description)}")
        from twin.dataset.spec import bundled_specs, load_spec, spec_path
        for name in bundled_specs():
            spec = load_spec(spec_path(name))
            print(f"{name} (dataset spec, twin dataset {name} -o DIR): {_one_line(spec.description)}")
    elif args.what == "effects":
        _effects(args.machine)
    else:
        for name, params in INSTRUMENTS.items():
            print(name)
            for p in params:
                print(f"    {p.describe()}")
    return 0
