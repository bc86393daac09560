"""The materials a user gives a prepared twin (material name -> replacement
:class:`geometries.materials.Material`), checked against the machine and against what a machine
tool's structure may be made of (:data:`PLAUSIBLE_MATERIAL`)."""

from __future__ import annotations

from twin import limits
from twin.errors import InputError

SOURCE = "PreparedTwin"     # the source named in errors about a PreparedTwin's arguments
MATERIAL_PROPERTIES = ("conductivity", "density", "specific_heat", "youngs_modulus")   # positive [SI]


def part_materials(machine, materials, source: str = SOURCE, field: str = "materials") -> dict:
    """The replacement material of each part of ``machine`` from ``materials`` (material name ->
    :class:`geometries.materials.Material`), checked: a dict, every name a material some part of
    the machine is made of (nothing is ignored), every value a Material with finite properties
    (conductivity, density, specific heat, Young's modulus positive; Poisson's ratio between -1
    and 0.5; expansion finite)."""
    from geometries.materials import Material

    if materials is None:
        return {}
    if not isinstance(materials, dict):
        raise InputError(source, field, f"expected a dict of material name -> Material, got {materials!r}")
    used = sorted({p.material.name for p in machine.parts})
    for name, material in materials.items():
        if name not in used:
            raise InputError(source, f"{field}[{name!r}]", f"no part of machine {machine.name} is made of {name!r}; "
                                                           f"its materials: {', '.join(used)}")
        if not isinstance(material, Material):
            raise InputError(source, f"{field}[{name!r}]", f"expected a geometries.materials.Material (e.g. "
                                                           f"MATERIALS[{name!r}].scaled(conductivity=1.05)), got "
                                                           f"{material!r}")
        if material.name != name:   # the key names the parts' material, the Material another
            raise InputError(source, f"{field}[{name!r}]", f"holds the material {material.name!r}: a replacement keeps "
                                                           f"its name (MATERIALS[{name!r}].scaled(...) or "
                                                           f"dataclasses.replace(..., name={name!r}))")
        values = {k: getattr(material, k) for k in MATERIAL_PROPERTIES + ("poisson_ratio", "expansion")}
        bad = [k for k, v in values.items() if not limits.is_finite_number(v) or (k in MATERIAL_PROPERTIES and v <= 0)
               or (k == "poisson_ratio" and not -1.0 < v < 0.5)]
        if bad:
            raise InputError(source, f"{field}[{name!r}].{bad[0]}", f"{values[bad[0]]!r} is not a possible value "
                                                                    "(finite; positive; Poisson's ratio from -1 to 0.5)")
        values["expansion_band"] = material.expansion_band
        for key, (lo, hi, unit) in PLAUSIBLE_MATERIAL.items():
            v = values[key]
            if not limits.is_number(v) or not lo <= v <= hi:
                raise InputError(source, f"{field}[{name!r}].{key}", f"{v!r} {unit} is outside what a machine "
                                                                     f"structure is made of, {lo:g} to {hi:g} {unit}")
    return {p.name: materials[p.material.name] for p in machine.parts if p.material.name in materials}


# what a machine tool's structure may be made of (cast iron, steels, granite, polymer concrete,
# aluminium, Invar, bronze; fibre composites' slightly negative expansion): property -> (lower,
# upper, unit); an expansion of 1 /K gave a drift of 584 m
PLAUSIBLE_MATERIAL = {"conductivity": (0.1, 500.0, "W/(m K)"), "density": (500.0, 25000.0, "kg/m3"),
                      "specific_heat": (100.0, 5000.0, "J/(kg K)"), "youngs_modulus": (1e9, 1.2e12, "Pa"),
                      "expansion": (-2e-5, 1e-4, "1/K"), "expansion_band": (0.0, 0.99, "(fraction of alpha)")}
