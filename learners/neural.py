"""Neural-network thermal-error models: ``ann`` (MLP) and ``pso-bpnn`` (PSO-initialised backprop MLP).

Both map temperatures ``X`` (degC) to a thermal error ``y`` (um) through a multilayer perceptron
with ``tanh`` (MATLAB ``tansig``) hidden units and a linear output::

    h_0 = s(x),   h_l = phi(h_{l-1} W_l + b_l)  (l = 1..L),   y = s_y^-1(h_L W_out + b_out)

where ``s`` and ``s_y`` rescale every input and the target linearly to [-1, 1] using the training
range (MATLAB ``mapminmax``, seed 002 step 1, L71; a constant column maps to 0).

``ann``: scikit-learn's :class:`~sklearn.neural_network.MLPRegressor` on the scaled data. Presets
from the seeds: ``shape="4-10-1"`` (thesis/seed 001 4-10-1 ANN, seed 001 L371-L373; seed 000 used
26-10-1) and ``"5-8-8-1"`` (seed 002 L73-L79). Only the hidden sizes are taken from the string (the
input count is whatever ``X`` has); ``hidden_layer_sizes`` overrides ``shape``. The seeds do not
state the training algorithm; L-BFGS (good for the small data sets of these studies) is the default.

``pso-bpnn`` (seed 002 Section 2, L44-L120): the network's weights and biases are first searched by a
particle swarm (constriction PSO, seed 002 Eqs. 3-4, chi = 0.729, c1 = c2 = 2.05, 20 particles,
30 iterations, L83-L93), each particle being the whole weight vector (129 numbers for 5-8-8-1) and
its fitness the training mean squared error on the scaled data. The seed's fitness equation is lost
from the text (L97-L102); the reconstruction ``F = (1/N) sum_a sum_b (p_ab - q_ab)^2`` is used.
The swarm's best then initialises batch back-propagation (gradient descent with momentum 0.9 on
1/2 MSE, learning rate 0.1, at most 300 epochs, stopping when the MSE reaches the goal 1e-4, seed 002
L79; the momentum constant is not in the seed, 0.9 is MATLAB's traingdm/traingdx default). The small MLP
is written here in numpy because scikit-learn cannot start from given weights cleanly.
Backprop for the loss E = 1/(2N) sum (o - t)^2, with delta_L = (o - t)/N at the output and
delta_{l-1} = (delta_l W_l^T) * phi'(z_{l-1}) below it; dE/dW_l = h_{l-1}^T delta_l,
dE/db_l = sum delta_l. phi' = 1 - h^2 (tanh) or h (1 - h) (sigmoid).

Optional structure search (seed 002 abstract, L19/L63, says PSO also picks the hidden sizes; its
method section fixes h = 8 from the range [3, 13]): ``hidden_search=(lo, hi)`` appends one
continuous coordinate per hidden layer to each particle, decoded as ``floor`` into ``lo..hi``, with
the weights held at the largest size and cropped. The training MSE always favours the largest
network, so the rows are split in time: the swarm fits the weights on the first rows (its fitness
the MSE there), every size the swarm visits keeps its best particle, and the size whose best
particle has the least MSE on the last ``validation_fraction`` of the rows (chronological hold-out,
never seen by the swarm) is chosen; back-propagation then trains that network on all rows.
"""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPRegressor

from learners._checks import (MAX_EPOCHS, MAX_ITERATIONS, MAX_PARTICLES, check_choice, check_fit_data, check_fraction,
                              check_int, check_non_negative, check_positive, check_predict_data, check_sizes,
                              model_name)
from learners.pso import pso_minimize
from learners.registry import register_learner
from twin.errors import InputError

__all__ = ["ANN", "PSOBPNN", "parse_shape"]


def parse_shape(shape: str) -> tuple[int, ...]:
    """Hidden sizes of an ``"in-h1-...-out"`` string, e.g. ``"5-8-8-1" -> (8, 8)``."""
    try:
        parts = [int(p) for p in str(shape).split("-")]
    except ValueError:
        raise ValueError(f"shape must look like '4-10-1', got {shape!r}") from None
    if len(parts) < 3 or min(parts) < 1 or parts[-1] != 1:
        raise ValueError(f"shape must be 'inputs-hidden...-1' with positive sizes, got {shape!r}")
    return tuple(parts[1:-1])


def _minmax_fit(a):
    lo, hi = a.min(axis=0), a.max(axis=0)
    span = np.where(hi - lo > 0, hi - lo, np.inf)
    return lo, span


def _minmax(a, lo, span):
    """Map to [-1, 1] over the training range (constant columns -> 0)."""
    return np.where(np.isfinite(span), 2.0 * (a - lo) / span - 1.0, 0.0)


def _unminmax(z, lo, span):
    return np.where(np.isfinite(span), (z + 1.0) * span / 2.0 + lo, lo)


@register_learner("ann")
class ANN(RegressorMixin, BaseEstimator):
    """MLP regressor with [-1, 1] input/target scaling (seeds 000-002 ANN baselines).

    Parameters
    ----------
    shape : str, default "4-10-1"          preset; hidden sizes are the middle numbers
    hidden_layer_sizes : tuple or None     overrides ``shape``
    activation : {"tanh", "logistic", "relu"}, default "tanh"
    solver : {"lbfgs", "adam", "sgd"}, default "lbfgs"
    alpha : float, default 1e-4            L2 penalty (on scaled data)
    max_iter : int, default 2000
    random_state : int or None
    """

    def __init__(self, shape="4-10-1", hidden_layer_sizes=None, activation="tanh", solver="lbfgs",
                 alpha=1e-4, max_iter=2000, random_state=None):
        self.shape = shape
        self.hidden_layer_sizes = hidden_layer_sizes
        self.activation = activation
        self.solver = solver
        self.alpha = alpha
        self.max_iter = max_iter
        self.random_state = random_state

    def _check_params(self):
        if self.hidden_layer_sizes is not None:
            hidden = check_sizes(self, "hidden_layer_sizes", self.hidden_layer_sizes)
        else:
            try:
                hidden = parse_shape(self.shape)
            except ValueError as err:
                raise InputError(model_name(self), "shape", str(err)) from None
        check_choice(self, "activation", self.activation, ("tanh", "logistic", "relu"))
        check_choice(self, "solver", self.solver, ("lbfgs", "adam", "sgd"))
        check_non_negative(self, "alpha", self.alpha)
        check_int(self, "max_iter", self.max_iter, maximum=MAX_EPOCHS)
        return hidden

    def fit(self, X, y):
        hidden = self._check_params()
        X, y = check_fit_data(self, X, y)
        self.x_lo_, self.x_span_ = _minmax_fit(X)
        self.y_lo_, self.y_span_ = _minmax_fit(y)
        mlp = MLPRegressor(hidden_layer_sizes=hidden, activation=self.activation, solver=self.solver,
                           alpha=self.alpha, max_iter=self.max_iter, random_state=self.random_state)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConvergenceWarning)
            mlp.fit(_minmax(X, self.x_lo_, self.x_span_), _minmax(y, self.y_lo_, self.y_span_))
        self.converged_ = not any(issubclass(w.category, ConvergenceWarning) for w in caught)
        self.hidden_layer_sizes_ = hidden
        self.n_iter_ = mlp.n_iter_
        self.mlp_ = mlp
        return self

    def predict(self, X):
        X = check_predict_data(self, X, "mlp_")
        z = self.mlp_.predict(_minmax(X, self.x_lo_, self.x_span_))
        return _unminmax(np.ravel(z), self.y_lo_, self.y_span_)


def _act(z, kind):
    return np.tanh(z) if kind == "tanh" else 1.0 / (1.0 + np.exp(-z))


def _act_grad(h, kind):
    return 1.0 - h * h if kind == "tanh" else h * (1.0 - h)


def _layer_shapes(n_in, hidden):
    sizes = [n_in, *hidden, 1]
    return [(sizes[i], sizes[i + 1]) for i in range(len(sizes) - 1)]


def _n_weights(shapes):
    return sum(a * b + b for a, b in shapes)


def _unpack(vec, shapes):
    params, k = [], 0
    for a, b in shapes:
        W = vec[k:k + a * b].reshape(a, b)
        k += a * b
        params.append((W, vec[k:k + b]))
        k += b
    return params


def _forward(params, X, kind):
    """Activations of every layer; the last entry is the (linear) network output, shape (n,)."""
    acts = [X]
    h = X
    for i, (W, b) in enumerate(params):
        z = h @ W + b
        h = z if i == len(params) - 1 else _act(z, kind)
        acts.append(h)
    acts[-1] = acts[-1][:, 0]
    return acts


def _mse(params, X, t, kind):
    with np.errstate(over="ignore", invalid="ignore"):
        out = _forward(params, X, kind)[-1]
        return float(np.mean((out - t) ** 2))


def _backprop(params, X, t, kind, learning_rate, epochs, goal, momentum):
    """Batch gradient descent on E = 1/(2N) sum (o - t)^2; returns (params, MSE per epoch)."""
    params = [(W.copy(), b.copy()) for W, b in params]
    velocity = [(np.zeros_like(W), np.zeros_like(b)) for W, b in params]
    n = X.shape[0]
    curve = []
    for _ in range(int(epochs)):
        acts = _forward(params, X, kind)
        err = acts[-1] - t
        mse = float(np.mean(err ** 2))
        curve.append(mse)
        if mse <= goal or not np.isfinite(mse):
            break
        delta = (err / n)[:, None]
        grads = []
        for i in range(len(params) - 1, -1, -1):
            W, _ = params[i]
            grads.append((acts[i].T @ delta, delta.sum(axis=0)))
            if i > 0:
                delta = (delta @ W.T) * _act_grad(acts[i], kind)
        grads.reverse()
        for i, ((W, b), (gW, gb)) in enumerate(zip(params, grads)):
            vW, vb = velocity[i]
            vW = momentum * vW - learning_rate * gW
            vb = momentum * vb - learning_rate * gb
            velocity[i] = (vW, vb)
            params[i] = (W + vW, b + vb)
    return params, np.array(curve)


@register_learner("pso-bpnn")
class PSOBPNN(RegressorMixin, BaseEstimator):
    """Back-propagation MLP whose initial weights come from a particle swarm (seed 002).

    Parameters (defaults from seed 002 L77-L93)
    ----------
    hidden_layer_sizes : tuple, default (8, 8)      5-8-8-1 network of the seed
    activation : {"tanh", "sigmoid"}, default "tanh"
    learning_rate : float, default 0.1              BP step on scaled data
    epochs : int, default 300                       BP epochs (upper bound; 0: the swarm's weights as found)
    goal : float, default 1e-4                      stop BP when the scaled training MSE <= goal
    momentum : float, default 0.9                   momentum constant of the BP step; the seed names
                                                    only the learning rate, 0.9 is MATLAB's
                                                    traingdm/traingdx default (0 = plain traingd)
    n_particles : int, default 20
    n_iterations : int, default 30
    pso_variant : {"constriction", "inertia"}, default "constriction"
    weight_bound : float, default 1.0               PSO searches weights in [-bound, bound] (the
                                                    seed does not state the box; scaled data)
    hidden_search : (int, int) or None              PSO also picks each hidden size in lo..hi
    validation_fraction : float, default 0.2        hold-out tail used when hidden_search is set, in (0, 1)
    random_state : int or None

    Attributes: ``hidden_layer_sizes_``, ``coefs_``/``intercepts_`` (trained weights per layer),
    ``pso_fun_`` (the swarm's fitness of the particle back-propagation starts from: the scaled
    training MSE; with ``hidden_search``, on the rows before the hold-out), ``loss_curve_`` (BP
    training MSE per epoch, scaled units); with ``hidden_search`` also ``hidden_scores_`` (each
    visited size's best particle's scaled MSE on the hold-out tail) and ``validation_mse_`` (the
    chosen size's).
    """

    def __init__(self, hidden_layer_sizes=(8, 8), activation="tanh", learning_rate=0.1, epochs=300,
                 goal=1e-4, momentum=0.9, n_particles=20, n_iterations=30, pso_variant="constriction",
                 weight_bound=1.0, hidden_search=None, validation_fraction=0.2, random_state=None):
        self.hidden_layer_sizes = hidden_layer_sizes
        self.activation = activation
        self.learning_rate = learning_rate
        self.epochs = epochs
        self.goal = goal
        self.momentum = momentum
        self.n_particles = n_particles
        self.n_iterations = n_iterations
        self.pso_variant = pso_variant
        self.weight_bound = weight_bound
        self.hidden_search = hidden_search
        self.validation_fraction = validation_fraction
        self.random_state = random_state

    def _decode(self, vec, n_in, max_hidden):
        """Split a particle into hidden sizes and cropped layer parameters."""
        n_layers = len(max_hidden)
        if self.hidden_search is None:
            hidden = max_hidden
            weights = vec
        else:
            lo, hi = self.hidden_search
            hidden = tuple(int(min(max(np.floor(s), lo), hi)) for s in vec[:n_layers])
            weights = vec[n_layers:]
        full = _unpack(weights, _layer_shapes(n_in, max_hidden))
        sizes = [n_in, *hidden, 1]
        params = [(W[:sizes[i], :sizes[i + 1]].copy(), b[:sizes[i + 1]].copy()) for i, (W, b) in enumerate(full)]
        return hidden, params

    def _check_params(self):
        check_sizes(self, "hidden_layer_sizes", self.hidden_layer_sizes)
        check_choice(self, "activation", self.activation, ("tanh", "sigmoid"))
        check_positive(self, "learning_rate", self.learning_rate)
        check_int(self, "epochs", self.epochs, minimum=0, maximum=MAX_EPOCHS)
        check_non_negative(self, "goal", self.goal)
        check_fraction(self, "momentum", self.momentum)
        check_int(self, "n_particles", self.n_particles, maximum=MAX_PARTICLES)
        check_int(self, "n_iterations", self.n_iterations, minimum=0, maximum=MAX_ITERATIONS)
        check_choice(self, "pso_variant", self.pso_variant, ("constriction", "inertia"))
        check_positive(self, "weight_bound", self.weight_bound)
        check_fraction(self, "validation_fraction", self.validation_fraction, zero=False)
        if self.hidden_search is not None:
            hs = self.hidden_search
            if isinstance(hs, (str, bytes)) or not hasattr(hs, "__len__") or len(hs) != 2:
                raise InputError(model_name(self), "hidden_search", f"must be (lo, hi) or None, got {hs!r}")
            lo = check_int(self, "hidden_search", hs[0])
            if check_int(self, "hidden_search", hs[1]) < lo:
                raise InputError(model_name(self), "hidden_search", f"must be (lo, hi) with 1 <= lo <= hi, got {hs!r}")

    def fit(self, X, y):
        self._check_params()
        X, y = check_fit_data(self, X, y)
        self.x_lo_, self.x_span_ = _minmax_fit(X)
        self.y_lo_, self.y_span_ = _minmax_fit(y)
        Xs = _minmax(X, self.x_lo_, self.x_span_)
        ts = _minmax(y, self.y_lo_, self.y_span_)
        n_in = X.shape[1]
        n_layers = len(tuple(self.hidden_layer_sizes))
        if self.hidden_search is None:
            max_hidden = tuple(int(h) for h in self.hidden_layer_sizes)
            lower_h = upper_h = np.empty(0)
            X_fit, t_fit = Xs, ts
        else:
            lo, hi = (int(v) for v in self.hidden_search)
            if not 1 <= lo <= hi:
                raise ValueError(f"hidden_search must be (lo, hi) with 1 <= lo <= hi, got {self.hidden_search}")
            max_hidden = (hi,) * n_layers
            lower_h, upper_h = np.full(n_layers, float(lo)), np.full(n_layers, hi + 1.0 - 1e-9)
            n_val = max(1, int(round(self.validation_fraction * len(y))))
            if n_val >= len(y):
                raise InputError(model_name(self), "validation_fraction",
                                 f"leaves no rows before the hold-out of {n_val} of {len(y)} rows")
            X_fit, t_fit = Xs[:-n_val], ts[:-n_val]
        n_w = _n_weights(_layer_shapes(n_in, max_hidden))
        lower = np.concatenate([lower_h, np.full(n_w, -float(self.weight_bound))])
        upper = np.concatenate([upper_h, np.full(n_w, float(self.weight_bound))])
        best_of_size: dict[tuple, tuple[float, np.ndarray]] = {}

        def fitness(vec):
            hidden, params = self._decode(vec, n_in, max_hidden)
            value = _mse(params, X_fit, t_fit, self.activation)
            if np.isfinite(value) and (hidden not in best_of_size or value < best_of_size[hidden][0]):
                best_of_size[hidden] = (value, vec.copy())
            return value

        res = pso_minimize(fitness, lower, upper, n_particles=self.n_particles,
                           n_iterations=self.n_iterations, variant=self.pso_variant,
                           random_state=self.random_state)
        start, start_fun = res.x, float(res.fun)
        if self.hidden_search is not None and best_of_size:
            held = {h: _mse(self._decode(v, n_in, max_hidden)[1], Xs[-n_val:], ts[-n_val:], self.activation)
                    for h, (_, v) in sorted(best_of_size.items())}
            chosen = min(held, key=lambda h: (np.nan_to_num(held[h], nan=np.inf), sum(h)))   # ties: the smaller
            start_fun, start = best_of_size[chosen]
            self.hidden_scores_ = {h: float(v) for h, v in held.items()}
            self.validation_mse_ = float(held[chosen])
        hidden, params = self._decode(start, n_in, max_hidden)
        params, curve = _backprop(params, Xs, ts, self.activation, self.learning_rate, self.epochs,
                                  self.goal, self.momentum)
        self.hidden_layer_sizes_ = hidden
        self.coefs_ = [W for W, _ in params]
        self.intercepts_ = [b for _, b in params]
        self.pso_fun_ = float(start_fun)
        self.loss_curve_ = curve
        return self

    def predict(self, X):
        X = check_predict_data(self, X, "coefs_")
        params = list(zip(self.coefs_, self.intercepts_))
        out = _forward(params, _minmax(X, self.x_lo_, self.x_span_), self.activation)[-1]
        return _unminmax(out, self.y_lo_, self.y_span_)
