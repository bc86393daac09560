"""The room beyond uniform still air: a cabinet, stratified air, a door draft, the sun, a slow floor.

Each acts on the machine's roles (the skin, its front and rear, the cabinet face, the floor
contact); every load is still a fixed spatial pattern times a time signal (see
:mod:`twin.effects.base`).
"""

from __future__ import annotations

import numpy as np

from twin.effects.base import (Convection, Effect, Parameter, SurfaceHeatFlux, Uncertain, constant, first_order_lag,
                               register_effect)
from twin.errors import InputError
from twin.fem.regions import facet_centres, role_facets


@register_effect
class ElectricalCabinet(Effect):
    """Heat of the electrical cabinet released beside the structure's ``cabinet.face`` (the
    C-frame: the column's left, -x, side).

    The cabinet's losses (drives, transformer, power supply) warm the air and radiate onto the
    adjacent column face; the part that reaches the structure is a uniform surface flux

        q = (P_standby + P_run [n(t) > 0]) / A_side   [W/m2]  on ``column_side_left``,

    P_standby while the machine is powered, P_run more while the spindle turns.
    """

    name = "electrical_cabinet"
    strength = "power"
    linear = True
    summary = "cabinet losses onto the column's left side face, P = P_standby + P_run [spindle on]"
    reference = "Mayr et al., CIRP Annals 61/2 (2012) 771-791, sec. 3.2 (internal heat sources, cabinets)"
    roles = ("cabinet.face",)
    parameters = (
        Parameter("power", "power", 40.0, 0.0, 1000.0, "heat reaching the column while the machine is powered"),
        Parameter("running_power", "power", 0.0, 0.0, 1000.0, "additional heat while the spindle turns"),
    )
    uncertain = (
        Uncertain("power", 10.0, 400.0, "cabinet losses (drives, supply) and how much of them reaches the column",
                  linear=True),
    )

    def loads(self, mm, scenario, p):
        base, run = p["power"], p["running_power"]
        return [SurfaceHeatFlux(self.name, role_facets(mm, "cabinet.face"),
                                lambda t: base + run * (np.abs(scenario.spindle_speed(t)) > 0))]


SKIN_H = Parameter("h", "heat_transfer_coefficient", 8.0, 0.5, 50.0, "skin coefficient (same as ambient_convection.h)")


class LayeredAir(Effect):
    """Base of the effects that layer the room air by height, T_air(z, t) = T_air(t) + c (z - z_ref)
    f(t), as :meth:`layer` gives (c, z_ref [m], f): with linear convection the skin flux
    h c (z - z_ref) f(t) (:func:`linear_in_height`), and the same change in the model's air
    (:meth:`air_change`, what an air sensor reads)."""

    def layer(self, scenario, p):
        raise NotImplementedError

    def loads(self, mm, scenario, p):
        c, z_ref, shape = self.layer(scenario, p)
        return linear_in_height(mm, self.name, p["h"] * c, z_ref, shape)

    def air_change(self, z, t, scenario, p):
        c, z_ref, shape = self.layer(scenario, p)
        return c * shape(np.asarray(t, float))[:, None] * (np.asarray(z, float)[None, :] - z_ref)


@register_effect
class AmbientStratification(LayeredAir):
    """Room air warmer with height: T_air(z, t) = T_air(t) + g (z - z_ref).

    Convection is linear, so on every skin face h (T - T_air - g (z - z_ref)) = h (T - T_air)
    - h g (z - z_ref): the stratification adds to the uniform ``ambient_convection`` a surface
    flux q(z) = h g (z - z_ref) [W/m2] (a *difference* model, linear in g), placed facet by facet
    at the facet centroid's height (:func:`linear_in_height`), so the total is h g sum A (z - z_ref).
    ``h`` should equal the ``ambient_convection`` h (both default 8 W/m2K).
    """

    name = "ambient_stratification"
    strength = "gradient"
    linear = True
    summary = "vertical air-temperature gradient g: extra flux h g (z - z_ref) on the skin"
    reference = "ISO 230-3:2020 Annex (environmental temperature variation); VDI 2078 (room air stratification)"
    roles = ("structure.skin",)
    parameters = (
        Parameter("gradient", "temperature_gradient", 0.5, -5.0, 5.0, "air temperature rise per metre of height g"),
        Parameter("reference_height", "length", 1.0, 0.0, 3.0, "height z_ref where the air is at the room temperature"),
        SKIN_H,
    )
    uncertain = (
        Uncertain("gradient", -0.5, 2.0, "halls range from well mixed to strongly layered (VDI 2078)", linear=True),
    )
    def layer(self, scenario, p):
        """g (z - z_ref) at every instant."""
        return p["gradient"], p["reference_height"], lambda t: np.ones(np.shape(t))


@register_effect
class StratifiedSwing(LayeredAir):
    """The room's swing grows with height: warm air pools under the roof by day and the top of the
    hall cools most at night, so T_air(z, t) = T_air(t) + s (z - z_ref) (T_air(t) - T_air(0)).

    As for ``ambient_stratification`` (linear convection, a difference model) this adds to the
    uniform ``ambient_convection`` the flux q(z, t) = h s (z - z_ref) (T_air(t) - T_air(0)) [W/m2]
    on the skin (:func:`linear_in_height`); with constant room air it is zero. A scenario's door events are left out of the swing (:func:`layered_swing`). s [1/m]
    is the extra swing per metre of height: the default 1 /m (the air at the column top, 1.4 m
    above z_ref, swings 2.4 times the room's reference air; a hall heated by day under its roof)
    is the upper end of plausible, chosen so that the C-frame meets the seed's ETVE magnitudes
    (README "The workshop").
    """

    name = "stratified_swing"
    strength = "growth"
    linear = True
    summary = "room swing growing with height: flux h s (z - z_ref) (T_air(t) - T_air(0)) on the skin"
    reference = "VDI 2078 (room air stratification); ISO 230-3:2020 Annex (environmental temperature variation)"
    roles = ("structure.skin",)
    parameters = (
        Parameter("growth", "inverse_length", 1.0, -2.0, 2.0, "extra swing per metre of height s"),
        Parameter("reference_height", "length", 0.5, 0.0, 3.0, "height z_ref where the air swings as the room's"),
        SKIN_H,
    )
    uncertain = (
        Uncertain("growth", 0.0, 1.5, "a well-mixed hall (0) to one heated under its roof by day; the default is "
                                      "chosen near the top of that range to meet the seed's ETVE magnitudes, and "
                                      "with constant room air it leaves no trace", linear=True),
    )

    def acts(self, scenario, params: dict | None = None) -> bool:
        """Only where the room air moves (door events aside, :func:`layered_swing`): a constant
        room without other events gives it nothing to act on."""
        a = scenario.ambient
        return a.kind != "constant" or any(not e.door for e in a.events)

    def layer(self, scenario, p):
        """s (z - z_ref) (T_air(t) - T_air(0)), the door events left out (:func:`layered_swing`)."""
        return p["growth"], p["reference_height"], lambda t: layered_swing(scenario, t)


def linear_in_height(mm, label: str, scale: float, z_ref: float, shape) -> list:
    """Surface flux q_f = scale (z_f - z_ref) shape(t) [W/m2] on the skin (z_f: facet centroid) as
    one load weighted by z_f - z_ref, of total power scale shape(t) sum A (z - z_ref) (one load, not
    one per height band: a reduced model needs few inputs); when that sum nearly cancels (z_ref
    near the skin's mean height) as two loads, above and below z_ref."""
    facets = role_facets(mm, "structure.skin")
    dz = facet_centres(mm, facets)[:, 2] - z_ref
    area = mm.facet_areas(facets)
    parts = [("", np.ones(dz.shape, bool))]
    if abs(np.sum(area * dz)) < 0.1 * np.sum(area * np.abs(dz)):
        parts = [(".above", dz > 0), (".below", dz < 0)]
    out = []
    for side, sel in parts:
        if sel.any():
            power = scale * float(np.sum(area[sel] * dz[sel]))
            out.append(SurfaceHeatFlux(f"{label}{side}", facets[sel], lambda t, w=power: w * shape(t),
                                       dz[sel] * np.sign(power or 1.0)))
    return out


def layered_swing(scenario, t: np.ndarray) -> np.ndarray:
    """T_air(t) - T_air(0) [K], both without the scenario's door events (a door open from t = 0
    moves neither): the outside air through a door is cold and dense and spreads along the floor,
    not under the roof (``door_stream`` carries it)."""
    doors = [e for e in getattr(scenario.ambient, "events", ()) if e.door]

    def air(times: np.ndarray) -> np.ndarray:
        return scenario.ambient_temperature(times) - sum((e(times) for e in doors), np.zeros(times.shape))

    return air(np.asarray(t, dtype=float)) - float(air(np.zeros(1))[0])


def event_window(t: np.ndarray, start: float, duration: float, period: float) -> np.ndarray:
    """1 inside events [start + i period, start + i period + duration), 0 outside; period 0: one event."""
    t = np.asarray(t, dtype=float)
    rel = t - start
    if period > 0:
        rel = np.where(rel >= 0, np.mod(rel, period), rel)
    return ((rel >= 0) & (rel < duration)).astype(float)


@register_effect
class DoorDraft(Effect):
    """A cold (or warm) air stream from an opened hall door hitting the machine's front
    (``structure.front``; the C-frame: its -y faces).

        -k dT/dn = h_d w(t) (T - T_air(t) - dT),  w(t) = 1 during events, else 0,

    added to the natural convection; events start at ``start`` and repeat every ``period``
    (0: one event). h_d is flat-plate forced convection, Re = v L / nu: laminar,
    Nu = 0.664 Re^0.5 Pr^(1/3), on a smooth face in a calm stream; turbulent,
    Nu = 0.037 Re^0.8 Pr^(1/3), where the door's gusts and the front's edges and covers trip the
    boundary layer. A draft of 1-3 m/s on faces of 0.2-1 m gives 3.9-15 W/(m2 K) laminar and
    6.1-20 W/(m2 K) turbulent (air at 20 degC); the default 15 W/(m2 K) is a tripped layer at
    about 2.5 m/s on a 0.4 m face, and the plausible range 3-25 W/(m2 K) spans 0.5 m/s laminar on
    1 m to 4 m/s turbulent on 0.2 m. Plausible, not measured.
    """

    name = "door_draft"
    strength = "h"
    linear = False
    summary = "air stream T_air + dT with h_d on the front faces during scheduled door openings"
    reference = "VDI Heat Atlas G4 (flat plate in parallel flow); Bryan, CIRP Annals 39/2 (1990) 645-656"
    roles = ("structure.front",)
    parameters = (
        Parameter("h", "heat_transfer_coefficient", 15.0, 0.0, 100.0, "draft heat-transfer coefficient h_d"),
        Parameter("temperature_difference", "temperature_difference", -8.0, -30.0, 30.0, "draft air minus room air dT"),
        Parameter("start", "time", 3600.0, 0.0, 30 * 86400.0, "time of the first opening"),
        Parameter("duration", "time", 1200.0, 10.0, 86400.0, "duration of each opening"),
        Parameter("period", "time", 0.0, 0.0, 7 * 86400.0, "repeat interval (0: a single event)"),
    )
    uncertain = (
        Uncertain("h", 3.0, 25.0, "draft speed 0.5-4 m/s on faces of 0.2-1 m, laminar to tripped turbulent "
                  "(flat-plate forced convection)"),
    )

    def check_params(self, params: dict[str, float], source: str) -> None:
        """Repeated openings each close before the next: duration < period (period 0: one event)."""
        if params["period"] > 0 and params["duration"] >= params["period"]:
            raise InputError(source, f"{self.name}.duration", f"each opening lasts {params['duration'] / 60:g} min, "
                                                              f"as long as or longer than the repeat interval "
                                                              f"{self.name}.period ({params['period'] / 60:g} min): the "
                                                              "door would never close; shorten the opening, lengthen "
                                                              "the period, or set period 0 for one event")

    def acts(self, scenario, params: dict | None = None) -> bool:
        """Only if the first opening falls within the run."""
        return (params or self.defaults())["start"] < scenario.duration

    def refusal(self, scenario, params: dict[str, float]) -> tuple[str, str] | None:
        if self.acts(scenario, params):
            return None
        return "start", (f"the first opening at {params['start'] / 3600:g} h lies at or after the end of the run "
                         f"({scenario.duration / 3600:g} h): the draft would do nothing; set door_draft.start within "
                         "the run, or leave the effect out")

    def loads(self, mm, scenario, p):
        facets = role_facets(mm, "structure.front")
        h, dT = p["h"], p["temperature_difference"]
        return [Convection(self.name, facets,
                           lambda t: h * event_window(t, p["start"], p["duration"], p["period"]),
                           lambda t: scenario.ambient_temperature(t) + dT)]


def daylight(t: np.ndarray, start_time_of_day: float, sunrise: float, sunset: float) -> np.ndarray:
    """Shape of the sun on a window face: sin(pi (tod - sunrise)/(sunset - sunrise)) by day, 0 at night
    (times of day [s]; sunset <= sunrise means no sun)."""
    tod = np.mod(start_time_of_day + np.asarray(t, dtype=float), 86400.0)
    phase = (tod - sunrise) / max(sunset - sunrise, 1.0)
    return np.where((phase > 0) & (phase < 1), np.sin(np.pi * np.clip(phase, 0, 1)), 0.0)


@register_effect
class SolarLoad(Effect):
    """Sunlight through a window onto the machine's rear (``structure.rear``; the
    C-frame: its +y faces) in day hours.

        q(t) = q_peak sin(pi (tod - t_rise) / (t_set - t_rise))  for t_rise < tod < t_set, else 0,

    absorbed flux [W/m2] spread uniformly on the rear faces (total P = q A_rear); the time of day
    is tod = scenario.ambient.start_time_of_day + t.
    """

    name = "solar_load"
    strength = "flux"
    linear = True
    summary = "absorbed sunlight on the rear faces, half-sine between sunrise and sunset"
    reference = "Duffie & Beckman, Solar Engineering of Thermal Processes, ch. 1-2"
    roles = ("structure.rear",)
    parameters = (
        Parameter("flux", "heat_flux", 40.0, 0.0, 800.0, "absorbed flux at solar noon q_peak"),
        Parameter("sunrise", "time", 7 * 3600.0, 0.0, 86400.0, "time of day the sun reaches the faces"),
        Parameter("sunset", "time", 19 * 3600.0, 0.0, 86400.0, "time of day the sun leaves the faces"),
    )
    uncertain = (
        Uncertain("flux", 5.0, 300.0, "diffuse light to direct sun through a window", linear=True),
    )

    def loads(self, mm, scenario, p):
        facets = role_facets(mm, "structure.rear")
        peak = p["flux"] * mm.facet_area(facets)
        t0 = getattr(scenario.ambient, "start_time_of_day", 0.0)
        return [SurfaceHeatFlux(self.name, facets, lambda t: peak * daylight(t, t0, p["sunrise"], p["sunset"]))]


@register_effect
class FloorLag(Effect):
    """A deep foundation following the room with a long time constant, in parallel with ``floor``.

        -k dT/dn = h_s (T - T_slow(t)),  tau_s dT_slow/dt = T_air(t) - T_slow,

    on the bed's foot (``floor_contact``). With ``floor`` also on, the two act in parallel: the
    foot sees a conductance h_c + h_s to the weighted floor temperature
    (h_c T_floor + h_s T_slow) / (h_c + h_s); without ``floor`` this is the only floor path.
    """

    name = "floor_lag"
    strength = "conductance"
    linear = False
    summary = "foot coupled to a slow foundation temperature lagging the room by tau_s"
    reference = "Bryan, CIRP Annals 39/2 (1990) 645-656 (foundation thermal inertia); ISO 230-3 Annex"
    roles = ("floor.contact",)
    parameters = (
        Parameter("conductance", "heat_transfer_coefficient", 20.0, 0.0, 1000.0, "foot conductance to the slow foundation h_s"),
        Parameter("lag", "time", 2 * 86400.0, 3600.0, 30 * 86400.0, "time constant tau_s of the foundation"),
    )
    uncertain = (
        Uncertain("conductance", 2.0, 200.0, "levelling feet to a grouted bed, as the floor's"),
    )

    def loads(self, mm, scenario, p):
        slow = first_order_lag(scenario.ambient_temperature, p["lag"], scenario.duration)
        return [Convection(self.name, role_facets(mm, "floor.contact"), constant(p["conductance"]), slow)]
