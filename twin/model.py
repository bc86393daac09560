"""The model a user simulates: a machine's set of effects with parameter values.

``--effects`` takes ``+name,-name`` to change the machine's default set
(``Machine.default_effects``), or plain ``a,b,c`` for an exact set; ``--set
effect.param=VALUE UNIT`` sets a parameter (effects and instruments alike). Unknown names, wrong
units, and effects whose roles the machine does not declare raise :class:`twin.errors.InputError`
(``command line: --set <key>: <message>``); nothing is ignored, and a parameter set twice is an
error, not the last value.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from geometries.regions import ROLES
from twin.effects import EFFECTS
from twin.errors import InputError, describe
from twin.io.comma_list import comma_items
from twin.limits import is_finite_number
from twin.observe.instruments import INSTRUMENTS
from twin.units import UnitError, format_quantity, parse_quantity

CLI = "command line"   # the source named in errors about --effects and --set


@dataclass
class ModelSpec:
    """Effects switched on and all parameter values (SI), effects' and instruments'."""

    effects: tuple[str, ...]
    params: dict[str, dict[str, float]] = field(default_factory=dict)

    def __post_init__(self):
        if isinstance(self.effects, str) or not isinstance(self.effects, (tuple, list)):
            raise InputError(CLI, "--effects", f"expected a tuple of effect names, got {self.effects!r}")
        for name in self.effects:
            if not isinstance(name, str):      # a list was an unhashable TypeError
                raise InputError(CLI, "--effects", f"expected effect names (texts), got {describe(name)}")
        twice = sorted({n for n in self.effects if list(self.effects).count(n) > 1}, key=str)
        if twice:   # applied twice, its heat would count twice
            raise InputError(CLI, f"--effects {twice[0]}", "named more than once; name each effect once")
        if not isinstance(self.params, dict) or not all(isinstance(v, dict) for v in self.params.values()):
            raise InputError(CLI, "--set", f"expected {{effect: {{parameter: value [SI]}}}}, got {self.params!r}")
        for name in self.effects:
            if name not in EFFECTS:
                raise InputError(CLI, f"--effects {name}", f"unknown effect; known: {', '.join(sorted(EFFECTS))}")
        full = {name: EFFECTS[name].defaults() for name in self.effects}
        full.update({name: {p.name: p.default for p in params} for name, params in INSTRUMENTS.items()})
        for group, values in self.params.items():
            if group not in full:
                raise InputError(CLI, f"--set {group}", "is not an effect that is switched on, nor an instrument")
            for key, value in values.items():
                if key not in full[group]:
                    raise InputError(CLI, f"--set {group}.{key}", f"unknown parameter; known: {', '.join(full[group])}")
                full[group][key] = self._checked(group, key, value)
        self.params = full

    def _checked(self, group: str, key: str, value) -> float:
        """A parameter's value [SI] given in Python: a finite number (NaN would run and mislead).
        Its bounds are checked where a user's model enters (:meth:`check_bounds`): the library
        itself runs effects at other strengths (zero, unit responses) to build its signatures."""
        if not is_finite_number(value):
            param = next(p for p in self.parameter_table(group) if p.name == key)
            raise InputError(CLI, f"--set {group}.{key}", f"expected a finite number [{param.unit}], got {value!r}")
        return float(value)

    def check_bounds(self, source: str = CLI) -> None:
        """Every parameter within its declared bounds, as ``--set`` asks: for a model built in
        Python and given to a diagnosis (a negative power or noise would be diagnosed as if
        possible)."""
        for group, values in self.params.items():
            for param in self.parameter_table(group):
                value = values[param.name]
                if not param.lower <= value <= param.upper:
                    raise InputError(source, f"spec {group}.{param.name}",
                                     f"{format_quantity(value, param.dimension)} is outside the bounds "
                                     f"{param.describe()}")
            if group in EFFECTS:
                EFFECTS[group].check_params(values, source)

    def parameter_table(self, group: str):
        return EFFECTS[group].parameters if group in EFFECTS else INSTRUMENTS[group]


def parse_effects(text: str | None, base: tuple[str, ...], always: tuple[str, ...] = ()) -> tuple[str, ...]:
    """``"+a,-b"`` edits ``base``; ``"a,b"`` replaces it; None keeps it. Each effect is named once,
    and the two forms are not mixed (``"a,+b"``): either would leave the result to the order.
    ``always``: effects switched on whatever the text says (an effects file's, in ``twin
    simulate``): naming one is allowed (``+hyd``, ``a,hyd``), removing one (``-hyd``) is refused."""
    if text is None:
        return tuple(base)
    if not isinstance(text, str):
        raise InputError(CLI, "--effects", f"expected one text such as '+a,-b' (edit the machine's defaults) or 'a,b' "
                                           f"(an exact set), got {text!r}" + (f": write {','.join(text)!r}" if
                                           isinstance(text, (list, tuple)) and all(isinstance(t, str) for t in text)
                                           else ""))
    if not text.replace(",", "").strip():
        raise InputError(CLI, "--effects", f"{'is empty' if not text.strip() else f'{text!r} names no effect'}: write "
                                           "+name,-name or a,b,c, or leave --effects out for the machine's defaults")
    items = comma_items(text, CLI, "--effects", "effect")      # "+a,,-b": an effect left out, never dropped
    if any(i in "+-" for i in items):
        raise InputError(CLI, f"--effects {text}", "names no effect; write +name,-name or a,b,c")
    names = [i.lstrip("+-") for i in items]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise InputError(CLI, f"--effects {text}", f"{', '.join(repeated)} named more than once; name each effect once")
    edits = [i[0] in "+-" for i in items]
    if any(edits) and not all(edits):
        raise InputError(CLI, f"--effects {text}", "mixes a set of effects (a,b) with edits of the defaults (+a,-b); "
                                                   "write one or the other")
    if not any(edits):
        chosen = items
    else:
        chosen = list(base)
        for item in items:
            sign, name = item[0], item[1:]
            if sign == "+" and name in base and name not in always:     # as "-x" of an absent x is refused
                raise InputError(CLI, f"--effects +{name}", f"{name} is already in the model (the machine's "
                                                            "defaults): the edit would change nothing; leave it out")
            if sign == "+" and name not in chosen:
                chosen.append(name)
            elif sign == "-":
                if name in always:
                    raise InputError(CLI, f"--effects -{name}", f"{name} comes from --effects-file, whose effects are "
                                                                f"always on; leave the file out to run without {name}")
                if name not in chosen:
                    raise InputError(CLI, f"--effects {name}", "cannot remove an effect that is not in the model")
                chosen.remove(name)
    for name in chosen:
        if name not in EFFECTS:
            raise InputError(CLI, f"--effects {name}", f"unknown effect; known: {', '.join(sorted(EFFECTS))}")
    return tuple(dict.fromkeys(chosen))


def parse_settings(items: list[str] | None, effects: tuple[str, ...]) -> dict[str, dict[str, float]]:
    """Parse ``["effect.param=VALUE UNIT", ...]`` into SI values, checking names and units. A
    bare text (not in a list) is refused: it would be read character by character."""
    out: dict[str, dict[str, float]] = {}
    if isinstance(items, str):
        raise InputError(CLI, "--set", f"expected a list of 'effect.param=VALUE UNIT' texts, got the text {items!r}: "
                                       f"write [{items!r}]")
    if items is not None and not isinstance(items, (list, tuple)):
        raise InputError(CLI, "--set", f"expected a list of 'effect.param=VALUE UNIT' texts, got {items!r}")
    for item in items or []:
        if not isinstance(item, str):
            raise InputError(CLI, "--set", f"expected 'effect.param=VALUE UNIT' texts, got {item!r}")
        if "=" not in item or "." not in item.split("=", 1)[0]:
            raise InputError(CLI, f"--set {item}", "expected effect.param=VALUE UNIT, e.g. spindle_motor.power=300W")
        key, value = item.split("=", 1)
        group, name = key.strip().split(".", 1)
        key = key.strip()
        if group in EFFECTS:
            if group not in effects:
                raise InputError(CLI, f"--set {key}", f"effect {group!r} is not switched on (add it with --effects +{group})")
            table = EFFECTS[group].parameters
        elif group in INSTRUMENTS:
            table = INSTRUMENTS[group]
        else:
            raise InputError(CLI, f"--set {key}", f"unknown effect or instrument {group!r}")
        param = next((p for p in table if p.name == name), None)
        if param is None:
            raise InputError(CLI, f"--set {key}", f"unknown parameter; known: {', '.join(p.name for p in table)}")
        try:
            v = parse_quantity(value.strip(), param.dimension)
        except UnitError as err:
            raise InputError(CLI, f"--set {key}", str(err)) from None
        if not param.lower <= v <= param.upper:
            raise InputError(CLI, f"--set {key}", f"{value.strip()} is outside the bounds {param.describe()}")
        if name in out.get(group, {}):
            raise InputError(CLI, f"--set {key}", "set more than once; give each parameter once")
        out.setdefault(group, {})[name] = v
    return out


def check_refusals(spec: ModelSpec, scenarios, source: str = CLI) -> None:
    """:class:`InputError` naming ``source`` where an effect switched on in ``spec`` cannot act
    in ``scenarios`` (one scenario, or a list: a diagnosis's measurements, of which it must act in
    one; :meth:`twin.effects.base.Effect.refusal`)."""
    many = isinstance(scenarios, (list, tuple))
    scenarios = list(scenarios) if many else [scenarios]
    for name in spec.effects:
        refused = [EFFECTS[name].refusal(sc, spec.params[name]) for sc in scenarios]
        if scenarios and all(refused):
            raise InputError(source, f"{name}.{refused[0][0]}", refused[0][1]
                             + (f" (in each of the {len(scenarios)} runs)" if len(scenarios) > 1 else ""))


def check_applicable(effects, machine) -> None:
    """Raise :class:`InputError` naming machine, effect and role if an effect in ``effects``
    needs a role ``machine`` does not declare, or is a custom effect read for another machine."""
    for name in effects:
        if not EFFECTS[name].applies_to(machine) and not EFFECTS[name].missing_roles(machine):
            raise InputError(CLI, f"--effects {name}", f"does not apply to machine {machine.name}: a custom effect read "
                                                       f"for machine {getattr(EFFECTS[name], 'machine', '?')} (its "
                                                       "regions name that machine's parts); read the file for this one")
        missing = EFFECTS[name].missing_roles(machine)
        if missing:
            role = missing[0]
            raise InputError(CLI, f"--effects {name}", f"does not apply to machine {machine.name}: it needs the role "
                                                f"{role!r} ({ROLES[role][1]}), which {machine.name} does not declare")


def applicable_effects(machine) -> list[str]:
    """Registered effects whose roles ``machine`` declares, sorted by name."""
    return sorted(name for name, e in EFFECTS.items() if e.applies_to(machine))


def model_spec(machine, effects: str | None = None, settings: list[str] | None = None,
               extra: tuple[str, ...] = ()) -> ModelSpec:
    """The model of ``machine`` from CLI-style strings: ``effects="+a,-b"`` edits the machine's
    default set, ``settings=["a.p=3 W"]``; every effect must apply to the machine. ``extra``
    effects (e.g. a user's custom effects) are switched on in addition."""
    from twin.limits import check_machine

    check_machine(machine, CLI)
    if isinstance(extra, str) or not isinstance(extra, (tuple, list)) or any(e not in EFFECTS for e in extra):
        raise InputError(CLI, "--effects-file", f"expected a tuple of registered effect names, got {extra!r}")
    chosen = tuple(dict.fromkeys(parse_effects(effects, tuple(machine.default_effects), tuple(extra)) + tuple(extra)))
    check_applicable(chosen, machine)
    spec = ModelSpec(chosen, with_machine_defaults(machine, chosen, parse_settings(settings, chosen)))
    for name in chosen:      # parameters possible one by one (parse_settings) and together
        EFFECTS[name].check_params(spec.params[name], CLI)
    return spec


def with_machine_defaults(machine, effects, params: dict) -> dict:
    """``params`` over the machine's own defaults (``Machine.effect_defaults``: a drive of another
    size than the registry's reference) for the ``effects`` switched on; what the user sets wins."""
    out = {name: dict(values) for name, values in params.items()}
    for name in effects:
        own = machine.effect_defaults.get(name)
        if own:
            for key, value in own.items():   # a machine's description, not user input: a bug if wrong
                param = next((q for q in EFFECTS[name].parameters if q.name == key), None)
                if param is None or not param.lower <= value <= param.upper:
                    raise ValueError(f"machine {machine.name}: effect_defaults {name}.{key} = {value!r} is not a "
                                     f"parameter of {name} within its bounds")
            out[name] = {**own, **out.get(name, {})}
    return out


def uncertain_range(machine, effect: str, u) -> tuple[float, float]:
    """The plausible range [SI] of the uncertain parameter ``u`` of ``effect`` on ``machine``: the
    registry's (:class:`twin.effects.base.Uncertain`, declared round the registry's default), or,
    where the machine sets its own default for that parameter (``Machine.effect_defaults``: a drive
    of another size), that range scaled by own / registry default, so it keeps its relative spread
    round the machine's value (the gantry's Z guideways: 0.6 W against the registry's range
    2-30 W, which a fit could never bring back to the model's own value), within the parameter's
    bounds. A default of zero on either side has no scale: the range is widened to hold it."""
    own = (machine.effect_defaults.get(effect) or {}).get(u.name) if machine is not None else None
    param = EFFECTS[effect].parameter(u.name)
    if own is None or own == param.default:
        return u.lower, u.upper
    if own > 0 and param.default > 0:
        scale = own / param.default
        return max(u.lower * scale, param.lower), min(u.upper * scale, param.upper)
    return min(u.lower, own), max(u.upper, own)


def default_spec(machine) -> ModelSpec:
    """The machine's default effects at their default parameters."""
    return model_spec(machine)
