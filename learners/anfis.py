"""First-order Takagi-Sugeno ANFIS with Gaussian membership functions: ``anfis-grid`` and ``anfis-fcm``.

Network (Jang 1993; thesis seed 000 Eqs. 3.1-3.6, L2128-L2268; seed 001 Section 3.4, L120-L126),
for inputs x = (x_1..x_d) and rules r = 1..R::

    mu_rj(x_j) = exp(-(x_j - c_rj)^2 / (2 sigma_rj^2))         layer 1, Gaussian MFs
    w_r        = prod_j mu_rj(x_j)                               layer 2, firing strength
    wbar_r     = w_r / sum_q w_q                                 layer 3, normalisation
    f_r        = p_r0 + sum_j p_rj x_j                           layer 4, first-order consequent
    y          = sum_r wbar_r f_r                                layer 5, output

Rules. ``anfis-grid`` (grid partition, seed 000 L2281-L2299): ``n_mfs`` MFs per input, centres
evenly spaced over the training range, widths such that neighbours cross at 0.5
(sigma = spacing / (2 sqrt(2 ln 2))), and one rule per combination, R = n_mfs^d (MFs are shared
between rules, so their gradients are summed). ``anfis-fcm`` (seed 001 L93, L124, L159;
MATLAB ``genfis3`` + ``anfis``): fuzzy c-means on the joined input-output training data with
``n_rules`` clusters; rule r takes the input part of centre r as its MF centres and the
membership-weighted spread as widths, sigma_rj^2 = sum_n u_nr^m (x_nj - c_rj)^2 / sum_n u_nr^m.
Deviation from ``genfis3``: FCM runs on z-scored inputs and output (``genfis3`` clusters raw units,
where the output in um would dominate the distances); on the seed-001 twin data clustering in raw
units does not test better (checked, not adopted).

Training, Jang's hybrid rule (seed 000 L2248-L2268; seed 001 L126): each epoch a forward pass
solves the consequents p by linear least squares (y is linear in p for fixed premises; normal
equations with a 1e-10 relative ridge), then a
backward pass moves the premise parameters (c, sigma) down the gradient of the training mean
squared error E::

    dE/dlog w_nr = (2/N) (y_n - t_n) wbar_nr (f_nr - y_n)
    dlog w_nr/dc_rj = (x_nj - c_rj) / sigma_rj^2,    dlog w_nr/dsigma_rj = (x_nj - c_rj)^2 / sigma_rj^3

with Jang's normalised step (the step moves the premise vector a distance ``learning_rate``) and his
step-size heuristics: x1.1 after four consecutive decreases of E, x0.9 after two up-down
alternations. The parameters of the epoch with the lowest training error are kept (as MATLAB's
``anfis`` returns).

Checking data (``validation_fraction``, default ``None``: off). Seed 001 trains on its heating and
cooling test "split into training and validation" (ratio and method not stated), with MATLAB's
``anfis`` and checking data, which returns the epoch of least *checking* error (hence the seed's
2-200 "iterations" per model). With ``validation_fraction = f`` the rows are cut into blocks of
``validation_block`` consecutive samples and every ``round(1/f)``-th block is held out as checking
data (blocks, not single rows: neighbouring 10 s samples are nearly equal, so single held-out rows
would check nothing); rules, consequents and premises are trained on the other rows, and the epoch
with the least checking error is kept (``best_epoch_``, ``checking_curve_``). Internally inputs and target are z-scored, so ``learning_rate`` is in standard
deviations; :meth:`rules_text` and the ``rule_*_`` attributes are in raw units (degC in, um out).
"""

from __future__ import annotations

import itertools

import numpy as np
import scipy.linalg
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import (MAX_EPOCHS, check_fit_data, check_float, check_int, check_positive, check_predict_data,
                              standardise)
from learners.fcm import fuzzy_cmeans
from learners.registry import register_learner
from twin.errors import InputError

__all__ = ["ANFISGrid", "ANFISFCM"]

_MIN_SIGMA = 1e-3  # smallest MF width, in standard deviations of the input


def _premise_terms(Z, C, S):
    """log firing strengths (n, R) of Gaussian rules with rule-level centres C and widths S (R, d)."""
    inv = 1.0 / (2.0 * S * S)
    return -((Z * Z) @ inv.T - 2.0 * Z @ (C * inv).T + (C * C * inv).sum(axis=1))


def _normalise(logw):
    logw = logw - logw.max(axis=1, keepdims=True)
    w = np.exp(logw)
    return w / w.sum(axis=1, keepdims=True)


def _consequents(Z, wbar, t):
    """Least-squares consequents P (R, d+1) = [p_r0, p_r1..p_rd] for fixed normalised strengths."""
    n, R = wbar.shape
    ext = np.column_stack([np.ones(n), Z])
    A = (wbar[:, :, None] * ext[:, None, :]).reshape(n, -1)
    # Normal equations with a tiny ridge (1e-10 of the mean diagonal): one BLAS product instead of
    # an SVD of the n x R(d+1) matrix, and a unique answer when some rule is never fired.
    gram = A.T @ A
    gram[np.diag_indices_from(gram)] += 1e-10 * max(float(np.trace(gram)) / gram.shape[0], 1e-300)
    try:
        p = scipy.linalg.solve(gram, A.T @ t, assume_a="pos")
    except (np.linalg.LinAlgError, scipy.linalg.LinAlgError):
        p = np.linalg.lstsq(A, t, rcond=None)[0]
    return p.reshape(R, -1)


def _premise_gradient(Z, t, wbar, F, out, C, S):
    """Gradient of the mean squared error over the rule-level centres and widths (R, d), consequents fixed."""
    G = (2.0 / len(t)) * (out - t)[:, None] * wbar * (F - out[:, None])       # dE/dlog w  (n, R)
    g_sum = G.sum(axis=0)[:, None]
    GZ, GZ2 = G.T @ Z, G.T @ (Z * Z)
    gC = (GZ - C * g_sum) / S ** 2
    gS = (GZ2 - 2.0 * C * GZ + C * C * g_sum) / S ** 3
    return gC, gS


def _checking_rows(n: int, fraction, block) -> np.ndarray | None:
    """Boolean mask of the checking rows: every ``round(1/fraction)``-th block of ``block`` consecutive rows
    (the last block of each period), or ``None`` when ``fraction`` is ``None``/0. A record too short for two
    checking blocks gets shorter blocks (``n // (2 round(1/fraction))`` rows)."""
    if not fraction:
        return None
    if not 0.0 < float(fraction) <= 0.5:
        raise ValueError(f"validation_fraction must be in (0, 0.5], got {fraction}")
    block = int(block)
    if block < 1:
        raise ValueError(f"validation_block must be >= 1, got {block}")
    period = max(2, int(round(1.0 / float(fraction))))
    block = max(1, min(block, n // (2 * period)))  # short records: smaller blocks, at least two checking blocks
    check = (np.arange(n) // block) % period == period - 1
    if check.sum() < 1 or (~check).sum() < 3:
        raise InputError("data", "rows", f"ANFIS checking split (fraction {fraction}, blocks of {block} rows) "
                                         f"leaves no checking or too few training rows out of {n}")
    return check


def _output(Z, wbar, P):
    F = Z @ P[:, 1:].T + P[:, 0]
    return (wbar * F).sum(axis=1), F


class _ANFISBase(RegressorMixin, BaseEstimator):
    """Shared hybrid training, prediction and rule printing; subclasses build the initial premises."""

    def _initial_premises(self, Z, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def _rule_params(self):
        idx = self.rule_mf_
        C = np.column_stack([self.mf_centers_[j][idx[:, j]] for j in range(idx.shape[1])])
        S = np.column_stack([self.mf_sigmas_[j][idx[:, j]] for j in range(idx.shape[1])])
        return C, S

    def _scatter(self, g_rule):
        idx = self.rule_mf_
        return [np.bincount(idx[:, j], weights=g_rule[:, j], minlength=len(self.mf_centers_[j]))
                for j in range(idx.shape[1])]

    def _evaluate(self, Z, t):
        C, S = self._rule_params()
        wbar = _normalise(_premise_terms(Z, C, S))
        P = _consequents(Z, wbar, t)
        out, F = _output(Z, wbar, P)
        return float(np.mean((out - t) ** 2)), P, wbar, F, out, C, S

    def _check_params(self):
        """Check the hyper-parameters (:mod:`learners._checks`); subclasses add their own."""
        check_int(self, "epochs", self.epochs, minimum=0, maximum=MAX_EPOCHS)
        check_positive(self, "learning_rate", self.learning_rate)
        if self.validation_fraction is not None:   # 0 switches the checking data off, as None
            check_float(self, "validation_fraction", self.validation_fraction, 0.0, 0.5)
        check_int(self, "validation_block", self.validation_block)

    def fit(self, X, y):
        self._check_params()
        X, y = check_fit_data(self, X, y, min_samples=3)
        Z, self.x_mean_, self.x_scale_ = standardise(X)
        t, self.y_mean_, self.y_scale_ = standardise(y)
        check = _checking_rows(len(t), self.validation_fraction, self.validation_block)
        if check is not None:
            Zc, tc, Z, t = Z[check], t[check], Z[~check], t[~check]
        self.mf_centers_, self.mf_sigmas_, self.rule_mf_ = self._initial_premises(Z, t)
        step = float(self.learning_rate)
        history, checking, best = [], [], None
        for epoch in range(int(self.epochs) + 1):
            err, P, wbar, F, out, C, S = self._evaluate(Z, t)
            history.append(err)
            score = err
            if check is not None:  # MATLAB anfis with checking data: keep the epoch of least checking error
                out_c, _ = _output(Zc, _normalise(_premise_terms(Zc, C, S)), P)
                score = float(np.mean((out_c - tc) ** 2))
                checking.append(score)
            if best is None or score < best[0]:
                best = (score, [c.copy() for c in self.mf_centers_], [s.copy() for s in self.mf_sigmas_], P, epoch)
            if epoch == int(self.epochs) or err <= 1e-14:
                break
            gC, gS = _premise_gradient(Z, t, wbar, F, out, C, S)
            gc, gs = self._scatter(gC), self._scatter(gS)
            norm = np.sqrt(sum(float(a @ a) + float(b @ b) for a, b in zip(gc, gs)))
            if norm <= 0 or not np.isfinite(norm):
                break
            for j in range(len(gc)):
                self.mf_centers_[j] = self.mf_centers_[j] - step * gc[j] / norm
                self.mf_sigmas_[j] = np.maximum(self.mf_sigmas_[j] - step * gs[j] / norm, _MIN_SIGMA)
            step = self._adapt_step(step, history)
        _, self.mf_centers_, self.mf_sigmas_, self.consequents_, self.best_epoch_ = best
        self.loss_curve_ = np.sqrt(np.array(history)) * self.y_scale_   # training RMSE per epoch, y units
        self.checking_curve_ = np.sqrt(np.array(checking)) * self.y_scale_ if check is not None else None
        self.n_rules_ = self.rule_mf_.shape[0]
        self._raw_rules()
        return self

    @staticmethod
    def _adapt_step(step, history):
        """Jang's heuristics on the last training errors: 4 decreases -> x1.1, 2 up-downs -> x0.9."""
        if len(history) >= 5:
            d = np.diff(history[-5:])
            if np.all(d < 0):
                return step * 1.1
            if d[0] < 0 < d[1] and d[2] < 0 < d[3] or d[0] > 0 > d[1] and d[2] > 0 > d[3]:
                return step * 0.9
        return step

    def _raw_rules(self):
        """Rule centres/widths (degC) and consequent y = a . x + c (um) in raw units."""
        C, S = self._rule_params()
        self.rule_centers_ = self.x_mean_ + self.x_scale_ * C
        self.rule_sigmas_ = self.x_scale_ * S
        P = self.consequents_
        self.rule_coefs_ = self.y_scale_ * P[:, 1:] / self.x_scale_
        self.rule_intercepts_ = self.y_mean_ + self.y_scale_ * (P[:, 0] - (P[:, 1:] * (self.x_mean_ / self.x_scale_)).sum(axis=1))

    def predict(self, X):
        X = check_predict_data(self, X, "consequents_")
        Z = (X - self.x_mean_) / self.x_scale_
        C, S = self._rule_params()
        out, _ = _output(Z, _normalise(_premise_terms(Z, C, S)), self.consequents_)
        return self.y_mean_ + self.y_scale_ * out

    def rules_text(self, feature_names=None) -> str:
        """The rules, one per line, in raw units::

            Rule 1: IF x1 is near 21.3 (sigma 0.8) AND x2 is near ... THEN y = 0.5*x1 - 1.2*x2 + 3.1
        """
        if not hasattr(self, "consequents_"):
            raise ValueError("fit the model before asking for its rules")
        d = self.n_features_in_
        names = list(feature_names) if feature_names is not None else [f"x{j + 1}" for j in range(d)]
        if len(names) != d:
            raise ValueError(f"need {d} feature names, got {len(names)}")
        lines = []
        for r in range(self.n_rules_):
            premise = " AND ".join(f"{names[j]} is near {self.rule_centers_[r, j]:.4g} "
                                   f"(sigma {self.rule_sigmas_[r, j]:.4g})" for j in range(d))
            terms = []
            for j in range(d):
                a = self.rule_coefs_[r, j]
                sign = "-" if a < 0 else "+"
                terms.append(f"{'-' if a < 0 else ''}{abs(a):.4g}*{names[j]}" if not terms else f"{sign} {abs(a):.4g}*{names[j]}")
            c = self.rule_intercepts_[r]
            terms.append(f"{'-' if c < 0 else '+'} {abs(c):.4g}")
            lines.append(f"Rule {r + 1}: IF {premise} THEN y = {' '.join(terms)}")
        return "\n".join(lines)


@register_learner("anfis-grid")
class ANFISGrid(_ANFISBase):
    """ANFIS with grid-partition rules (R = n_mfs ** n_inputs).

    Parameters
    ----------
    n_mfs : int, default 3            Gaussian MFs per input (seed 000: 5 inputs x 3 MFs = 243 rules)
    epochs : int, default 50          hybrid-learning epochs
    learning_rate : float, default 0.01   initial normalised step (standard deviations; MATLAB's 0.01)
    max_rules : int, default 1024     refuse larger grids (they grow as n_mfs ** n_inputs)
    validation_fraction : float or None, default None   share of rows held out as checking data
                                      (module docstring); the epoch of least checking error is kept
    validation_block : int, default 30   consecutive rows per checking block (30 = 5 min at 10 s)
    random_state : int or None        accepted for a uniform interface; grid training is deterministic

    Attributes: ``n_rules_``, ``mf_centers_``/``mf_sigmas_`` (per input, standardised units),
    ``rule_mf_`` (R, d) MF index of each rule, ``consequents_`` (R, d+1, standardised),
    ``rule_centers_``, ``rule_sigmas_``, ``rule_coefs_``, ``rule_intercepts_`` (raw units),
    ``loss_curve_`` (training RMSE per epoch, units of y), ``checking_curve_`` (checking RMSE per
    epoch, or ``None``), ``best_epoch_`` (the epoch whose parameters are kept).
    """

    def __init__(self, n_mfs=3, epochs=50, learning_rate=0.01, max_rules=1024, validation_fraction=None,
                 validation_block=30, random_state=None):
        self.n_mfs = n_mfs
        self.epochs = epochs
        self.learning_rate = learning_rate
        self.max_rules = max_rules
        self.validation_fraction = validation_fraction
        self.validation_block = validation_block
        self.random_state = random_state

    def _check_params(self):
        super()._check_params()
        check_int(self, "n_mfs", self.n_mfs)
        check_int(self, "max_rules", self.max_rules)

    def _initial_premises(self, Z, t):
        m, d = int(self.n_mfs), Z.shape[1]
        if m ** d > self.max_rules:
            raise InputError("anfis-grid", "n_mfs",
                             f"{m} MFs on {d} inputs make {m ** d} rules (> max_rules={self.max_rules}); "
                             "select fewer inputs or use anfis-fcm")
        centers, sigmas = [], []
        for j in range(d):
            lo, hi = float(Z[:, j].min()), float(Z[:, j].max())
            if m == 1 or hi <= lo:
                centers.append(np.full(m, (lo + hi) / 2.0))
                sigmas.append(np.full(m, max((hi - lo) / 2.0, 1.0)))
            else:
                centers.append(np.linspace(lo, hi, m))
                sigmas.append(np.full(m, (hi - lo) / (m - 1) / (2.0 * np.sqrt(2.0 * np.log(2.0)))))
        rule_mf = np.array(list(itertools.product(range(m), repeat=d)), dtype=int).reshape(-1, d)
        return centers, sigmas, rule_mf


@register_learner("anfis-fcm")
class ANFISFCM(_ANFISBase):
    """ANFIS whose rules come from fuzzy c-means clusters of the training data (seed 001 FCM-ANFIS).

    Parameters
    ----------
    n_rules : int, default 3          clusters = rules = MFs per input (seed 000 Machine B: 3;
                                      seed 001 Machine A: 6)
    epochs : int, default 50
    learning_rate : float, default 0.01
    fcm_m : float, default 2.0        FCM fuzzifier (not stated in the seeds; MATLAB default)
    validation_fraction, validation_block   checking data, as :class:`ANFISGrid`
    random_state : int or None        seeds the FCM initial centres

    Attributes as :class:`ANFISGrid`; ``mf_centers_[j]`` has one entry per rule.
    """

    def __init__(self, n_rules=3, epochs=50, learning_rate=0.01, fcm_m=2.0, validation_fraction=None,
                 validation_block=30, random_state=None):
        self.n_rules = n_rules
        self.epochs = epochs
        self.learning_rate = learning_rate
        self.fcm_m = fcm_m
        self.validation_fraction = validation_fraction
        self.validation_block = validation_block
        self.random_state = random_state

    def _check_params(self):
        super()._check_params()
        check_int(self, "n_rules", self.n_rules)
        check_float(self, "fcm_m", self.fcm_m, 1.0, above=True)

    def _initial_premises(self, Z, t):
        R, d = int(self.n_rules), Z.shape[1]
        res = fuzzy_cmeans(np.column_stack([Z, t]), R, m=self.fcm_m, random_state=self.random_state)
        um = res.membership ** self.fcm_m                                     # (n, R)
        C = res.centers[:, :d]
        var = (um.T @ (Z * Z) - 2.0 * C * (um.T @ Z) + C * C * um.sum(axis=0)[:, None]) / um.sum(axis=0)[:, None]
        S = np.maximum(np.sqrt(np.clip(var, 0.0, None)), 0.05)
        centers = [C[:, j].copy() for j in range(d)]
        sigmas = [S[:, j].copy() for j in range(d)]
        rule_mf = np.tile(np.arange(R)[:, None], (1, d))
        return centers, sigmas, rule_mf
