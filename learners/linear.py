"""Linear thermal-error models: multiple linear regression (MLR) and principal component regression (PCR).

Both predict a thermal error ``y`` (um, or the slope k in um/mm of seed 003) from temperatures
``X`` (degC) and expose the fitted model in raw units, ``y = intercept_ + X @ coef_``.

MLR, seed 003 Eq. (4) (L95)::

    k_i = beta_0 + beta_1 T_1 + ... + beta_n T_n + eps

solved by ordinary least squares; ``alpha > 0`` adds a ridge penalty ``alpha * ||beta||^2`` on the
slopes (not the intercept), ``beta = (Xc^T Xc + alpha I)^-1 Xc^T yc`` on centred data.

PCR, seed 003 Section 2.2 (L97-L117, steps L103-L107), Eqs. (5)-(6), (13)-(15)::

    z_j = (T_j - mean_j) / sd_j                 standardise (sd with n-1, i.e. PCA of the
                                                correlation matrix R = Z^T Z / (n-1))
    R v_k = lambda_k v_k                        principal components, lambda_1 >= lambda_2 >= ...
    C_k = Z v_k                                 component scores, k = 1..p
    y = b_0 + sum_k b_k C_k                     OLS on the retained components
    coef_ = V_p b / sd,  intercept_ = b_0 - mean . coef_     back-substitution (Eq. 15)

The seed keeps components by scree plot and cumulative explained variance > 85 %, so the default
``n_components=0.85`` keeps the fewest components whose cumulative variance fraction exceeds 0.85;
an integer keeps exactly that many. The seed (SPSS) regresses on factor scores ``C_k / sqrt(lambda_k)``;
that only rescales ``b_k``, so predictions and the back-substituted raw-unit equation are the same.
With every component kept PCR equals OLS (a known answer used in the tests).
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import check_count_fits, check_fit_data, check_int, check_non_negative, \
    check_predict_data, model_name, standardise
from learners.registry import register_learner
from twin.errors import InputError
from twin.limits import is_whole

__all__ = ["MLR", "PCR"]


@register_learner("mlr")
class MLR(RegressorMixin, BaseEstimator):
    """Multiple linear regression (seed 003 Eq. 4); ``alpha > 0`` gives ridge regression.

    Parameters
    ----------
    alpha : float, default 0.0
        Ridge penalty on the slopes, in (units of y / units of X)^-2 * units of y^2; 0 = OLS
        (minimum-norm least squares when the inputs are collinear).

    Attributes
    ----------
    coef_ : ndarray (n_features,)   slopes, units of y per unit of each input (e.g. um/degC)
    intercept_ : float              units of y
    """

    def __init__(self, alpha=0.0):
        self.alpha = alpha

    def _check_params(self):
        check_non_negative(self, "alpha", self.alpha)

    def fit(self, X, y):
        self._check_params()
        X, y = check_fit_data(self, X, y)
        x_mean, y_mean = X.mean(axis=0), y.mean()
        Xc, yc = X - x_mean, y - y_mean
        if self.alpha > 0:
            gram = Xc.T @ Xc + self.alpha * np.eye(X.shape[1])
            coef = np.linalg.solve(gram, Xc.T @ yc)
        else:
            coef = np.linalg.lstsq(Xc, yc, rcond=None)[0]
        self.coef_ = coef
        self.intercept_ = float(y_mean - x_mean @ coef)
        return self

    def predict(self, X):
        X = check_predict_data(self, X, "coef_")
        return X @ self.coef_ + self.intercept_


@register_learner("pcr")
class PCR(RegressorMixin, BaseEstimator):
    """Principal component regression (seed 003 Section 2.2): standardise, PCA, regress.

    Parameters
    ----------
    n_components : int or float, default 0.85
        int >= 1: number of components kept (at most the number of inputs: more is refused at
        fit); float in (0, 1): keep the fewest components whose cumulative explained-variance
        fraction exceeds it (seed 003 uses 85 %, L105-L107). Capped at the rank of the
        standardised data (``n_components_`` says how many were kept).

    Attributes
    ----------
    n_components_ : int
    components_ : ndarray (n_components_, n_features)   eigenvectors of the correlation matrix
    explained_variance_ : ndarray (n_features,)          all eigenvalues lambda_k, descending
    explained_variance_ratio_ : ndarray (n_features,)    lambda_k / sum(lambda)
    score_coef_ : ndarray (n_components_,)               b_k on the scores C_k = Z v_k
    coef_, intercept_ : raw-unit equation y = intercept_ + X @ coef_ (seed 003 Eq. 15)
    """

    def __init__(self, n_components=0.85):
        self.n_components = n_components

    def _check_params(self):
        nc = self.n_components
        if is_whole(nc):
            return check_int(self, "n_components", nc)
        ok = isinstance(nc, (float, np.floating)) and 0.0 < float(nc) < 1.0
        if not ok:
            raise InputError(model_name(self), "n_components", "must be an integer >= 1 (components kept) or a number "
                                                               f"in (0, 1) (explained-variance fraction), got {nc!r}")
        return float(nc)

    def _n_keep(self, ratio, rank):
        nc = self._check_params()
        if isinstance(nc, int):
            return int(min(nc, rank))
        k = int(np.searchsorted(np.cumsum(ratio), nc, side="right")) + 1
        return int(min(k, rank))

    def fit(self, X, y):
        nc = self._check_params()
        X, y = check_fit_data(self, X, y, min_samples=3)
        if isinstance(nc, int):
            check_count_fits(self, "n_components", nc, X.shape[1])
        Z, self.x_mean_, self.x_scale_ = standardise(X)
        n = X.shape[0]
        corr = Z.T @ Z / (n - 1)
        eigval, eigvec = np.linalg.eigh(corr)
        order = np.argsort(eigval)[::-1]
        eigval = np.clip(eigval[order], 0.0, None)
        eigvec = eigvec[:, order]
        # Deterministic sign: the largest-magnitude loading of each component is positive.
        signs = np.sign(eigvec[np.argmax(np.abs(eigvec), axis=0), np.arange(eigvec.shape[1])])
        eigvec = eigvec * np.where(signs == 0, 1.0, signs)
        total = eigval.sum()
        ratio = eigval / total if total > 0 else np.zeros_like(eigval)
        rank = max(1, int(np.sum(eigval > 1e-10 * max(eigval[0], 1e-300))))
        k = self._n_keep(ratio, rank)
        V = eigvec[:, :k]
        scores = Z @ V
        b = np.linalg.lstsq(scores - scores.mean(axis=0), y - y.mean(), rcond=None)[0]
        self.n_components_ = k
        self.components_ = V.T.copy()
        self.explained_variance_ = eigval
        self.explained_variance_ratio_ = ratio
        self.score_coef_ = b
        self.coef_ = (V @ b) / self.x_scale_
        self.intercept_ = float(y.mean() - self.x_mean_ @ self.coef_)
        return self

    def transform_scores(self, X):
        """Component scores ``C = Z V`` of new temperatures (n_samples, n_components_)."""
        X = check_predict_data(self, X, "coef_")
        return ((X - self.x_mean_) / self.x_scale_) @ self.components_.T

    def predict(self, X):
        X = check_predict_data(self, X, "coef_")
        return X @ self.coef_ + self.intercept_
