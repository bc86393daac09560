"""Name -> class registries for thermal-error learners and sensor selectors.

Modules register their estimators with ``@register_learner("name")`` or
``@register_selector("name")``; ``make_learner(name, **params)`` builds one by name.
"""

from __future__ import annotations

from twin.errors import InputError, describe

LEARNERS: dict[str, type] = {}
SELECTORS: dict[str, type] = {}


def _register(table: dict[str, type], kind: str, name: str):
    def decorate(cls: type) -> type:
        if name in table:
            raise RuntimeError(f"{kind} {name!r} registered twice")
        table[name] = cls
        cls.registry_name = name
        return cls

    return decorate


def register_learner(name: str):
    """Class decorator: register a scikit-learn regressor under ``name``."""
    return _register(LEARNERS, "learner", name)


def register_selector(name: str):
    """Class decorator: register a sensor-selection transformer under ``name``."""
    return _register(SELECTORS, "selector", name)


def _make(table: dict[str, type], kind: str, name: str, params: dict):
    if not isinstance(name, str):      # a list was an unhashable TypeError
        raise InputError("command line", kind, f"expected a {kind}'s name (one of {', '.join(sorted(table))}), "
                                               f"got {describe(name)}")
    if name not in table:
        raise InputError("command line", kind, f"unknown {kind} {name!r}; known: {', '.join(sorted(table))}")
    cls = table[name]
    known = cls._get_param_names()
    for key in params:
        if key not in known:
            raise InputError(name, key, f"unknown parameter of {kind} {name!r}; known: {', '.join(known) or 'none'}")
    if "random_state" in known and "random_state" not in params:
        params = {**params, "random_state": DEFAULT_RANDOM_STATE}
    est = cls(**params)
    if "random_state" in known:       # checked now, as the other hyper-parameters (it was only at fit)
        from learners._checks import check_seed
        check_seed(est, est.random_state)
    check = getattr(est, "_check_params", None)
    if check is not None:   # hyper-parameters checked now, before any fit (again at fit: set_params)
        check()
    return est


DEFAULT_RANDOM_STATE = 0   # what make_learner/make_selector seed a random start with unless told


def make_learner(name: str, **params):
    """Build the learner registered as ``name`` with hyper-parameters ``params``.

    An unknown name, an unknown parameter or a bad value (checked by the learner's
    ``_check_params``) is an :class:`InputError` naming it. A learner with a random start
    (ANFIS-FCM, the networks, PSO) gets ``random_state`` :data:`DEFAULT_RANDOM_STATE` unless one is
    given, so the same call gives the same model; scikit-learn's None (a fresh draw every fit)
    must be asked for."""
    return _make(LEARNERS, "learner", name, params)


def make_selector(name: str, **params):
    """Build the selector registered as ``name`` with hyper-parameters ``params`` (errors as
    :func:`make_learner`)."""
    return _make(SELECTORS, "selector", name, params)
