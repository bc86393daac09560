"""Element matrices of axis-aligned box ("brick") elements, vectorised over element shapes.

Every cell of our rectilinear grid is a box of size (dx, dy, dz), so its Jacobian is the constant
diag(dx, dy, dz)/2 and the element matrices depend only on the size and the material: they are
computed once per distinct (size, material) pair, in closed form by 2x2x2 Gauss quadrature,
which is exact for all the products below.

Heat: trilinear hexahedron (Q1), conductivity ``K_e = k int grad N . grad N^T dV`` and capacity
``M_e = rho c int N N^T dV``.

Elasticity: trilinear hexahedron with Wilson-Taylor incompatible modes (Q1 + 1-xi^2, 1-eta^2,
1-zeta^2 per displacement component, condensed statically per element). On box elements it
passes the patch test and represents pure bending exactly, so it does not shear-lock; and the
stress-free state of a linear temperature field (displacements quadratic in x, y, z) lies in its
space, so thermal bending is exact (E. L. Wilson et al., 1973; R. L. Taylor et al., 1976).
Thermal load: ``C_e = int B^T D m alpha N^T dV`` with m = (1, 1, 1, 0, 0, 0), so that the
nodal forces of a temperature rise dT are ``C_e dT``.
"""

from __future__ import annotations

import numpy as np

# corners of the reference cube [-1, 1]^3 in scikit-fem's local node order (see twin.fem.mesh)
CORNER_SIGNS = 2.0 * np.array(
    [[0, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1], [1, 1, 0], [0, 1, 1], [1, 0, 1], [1, 1, 1]], dtype=float
) - 1.0
_G = 1.0 / np.sqrt(3.0)
GAUSS = np.array([[a, b, c] for a in (-_G, _G) for b in (-_G, _G) for c in (-_G, _G)])  # weights all 1


def shape_q1(xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Trilinear shape functions N (n, 8) and their reference gradients dN (n, 8, 3) at xi (n, 3)."""
    s = CORNER_SIGNS
    f = 1.0 + xi[:, None, :] * s[None, :, :]  # (n, 8, 3)
    n = 0.125 * f.prod(axis=2)
    dn = np.empty(f.shape)
    dn[..., 0] = 0.125 * s[:, 0] * f[..., 1] * f[..., 2]
    dn[..., 1] = 0.125 * s[:, 1] * f[..., 0] * f[..., 2]
    dn[..., 2] = 0.125 * s[:, 2] * f[..., 0] * f[..., 1]
    return n, dn


def heat_matrices(size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit-property Q1 conduction and capacity matrices (m, 8, 8) for box sizes (m, 3) [m].

    Multiply by k [W/(m K)] and rho c [J/(m3 K)] respectively.
    """
    n, dn = shape_q1(GAUSS)
    half = 0.5 * size  # (m, 3): Jacobian diagonal
    det = half.prod(axis=1)  # (m,)
    grad = dn[None, :, :, :] / half[:, None, None, :]  # (m, q, 8, 3)
    k = np.einsum("mqai,mqbi->mab", grad, grad) * det[:, None, None]
    mass = np.einsum("qa,qb->ab", n, n)[None] * det[:, None, None]
    return k, mass


def _b_matrix(grad: np.ndarray) -> np.ndarray:
    """Engineering-strain matrix B (m, q, 6, 3*nb) from shape gradients (m, q, nb, 3).

    Strain order: xx, yy, zz, yz, xz, xy; displacement dofs interleaved (u0x, u0y, u0z, u1x, ...).
    """
    m, q, nb, _ = grad.shape
    b = np.zeros((m, q, 6, nb, 3))
    for i in range(3):
        b[:, :, i, :, i] = grad[..., i]
    b[:, :, 3, :, 1], b[:, :, 3, :, 2] = grad[..., 2], grad[..., 1]
    b[:, :, 4, :, 0], b[:, :, 4, :, 2] = grad[..., 2], grad[..., 0]
    b[:, :, 5, :, 0], b[:, :, 5, :, 1] = grad[..., 1], grad[..., 0]
    return b.reshape(m, q, 6, 3 * nb)


def elasticity_matrix(lam: np.ndarray, mu: np.ndarray) -> np.ndarray:
    """Isotropic D (m, 6, 6) [Pa] from Lame constants (engineering shear strains)."""
    d = np.zeros((len(lam), 6, 6))
    d[:, :3, :3] = lam[:, None, None]
    for i in range(3):
        d[:, i, i] += 2 * mu
        d[:, 3 + i, 3 + i] = mu
    return d


def _brick_gradients(xi: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Physical gradients (m, q, 11, 3) of the eight Q1 shape functions and the three incompatible
    modes P_i = 1 - xi_i^2 (gradient along i only, -2 xi_i) at reference points ``xi`` (q, 3) or
    (m, q, 3) of bricks with half-sizes ``half`` (m, 3) [m]."""
    xi = np.broadcast_to(xi, (len(half),) + np.shape(xi)[-2:])
    m, q, _ = xi.shape
    _, dn = shape_q1(xi.reshape(-1, 3))
    dp = np.zeros((m * q, 3, 3))
    for i in range(3):
        dp[:, i, i] = -2.0 * xi.reshape(-1, 3)[:, i]
    return np.concatenate([dn, dp], axis=1).reshape(m, q, 11, 3) / half[:, None, None, :]


def _condense(k: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Static condensation of the incompatible modes (the last 9 dofs): K_cc - K_ci K_ii^-1 K_ic and
    C_c - K_ci K_ii^-1 C_i, for stiffness k (m, 33, 33) and coupling c (m, 33, n)."""
    kcc, kci, kii = k[:, :24, :24], k[:, :24, 24:], k[:, 24:, 24:]
    return (kcc - kci @ np.linalg.solve(kii, np.transpose(kci, (0, 2, 1))),
            c[:, :24, :] - kci @ np.linalg.solve(kii, c[:, 24:, :]))


def _stiffness(size: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Uncondensed stiffness (m, 33, 33) [N/m] of bricks of ``size`` (m, 3) with elasticity D (m, 6, 6)."""
    half = 0.5 * size
    b = _b_matrix(_brick_gradients(GAUSS, half))
    db = np.einsum("mij,mqjb->mqib", d, b)
    return np.einsum("mqia,mqib->mab", b, db) * half.prod(axis=1)[:, None, None]


def _thermal_load(b: np.ndarray, d: np.ndarray, alpha: np.ndarray, det: np.ndarray) -> np.ndarray:
    """Uncondensed coupling (m, 33, 8) [N/K]: sum over the Gauss points of B^T D m alpha N^T det,
    for strain matrices ``b`` (m, q, 6, 33) at the points of a cell whose trilinear temperature
    N (the 2x2x2 Gauss points of that cell, Jacobian determinant ``det`` (m,) [m3]) loads them."""
    n, _ = shape_q1(GAUSS)
    dm = d[:, :, :3].sum(axis=2) * alpha[:, None]  # D m alpha: (m, 6)
    return np.einsum("mqia,mi,qn->man", b, dm, n) * det[:, None, None]


def elastic_matrices(size: np.ndarray, lam: np.ndarray, mu: np.ndarray, alpha: np.ndarray):
    """Condensed stiffness (m, 24, 24) [N/m] and thermal coupling (m, 24, 8) [N/K] of box elements.

    size (m, 3) [m], Lame constants lam, mu (m,) [Pa], expansion alpha (m,) [1/K].
    """
    half = 0.5 * size
    d = elasticity_matrix(lam, mu)
    b = _b_matrix(_brick_gradients(GAUSS, half))  # (m, q, 6, 33)
    return _condense(_stiffness(size, d), _thermal_load(b, d, alpha, half.prod(axis=1)))


def nested_coupling(size: np.ndarray, sub_size: np.ndarray, offset: np.ndarray, lam: np.ndarray,
                    mu: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """Thermal coupling (m, 24, 8) [N/K] of a brick of ``size`` (m, 3) [m] with the temperature of a
    smaller brick inside it (``sub_size``, its low corner at ``offset`` from the brick's): the
    nodal forces on the brick's eight corners from a trilinear temperature rise on the sub-brick's
    eight corners,

        C = int_sub B^T D m alpha N_sub^T dV,  condensed like :func:`elastic_matrices`' coupling.

    2x2x2 Gauss points of the sub-brick integrate it exactly (B is bilinear and N_sub trilinear
    there). Summed over the sub-bricks that tile the brick it is the coupling of an elastic cell
    to a finer temperature grid (:func:`twin.fem.assembly.assemble_nested_coupling`); with the
    sub-brick the brick itself it is :func:`elastic_matrices`' coupling.
    """
    inside = offset[:, None, :] + 0.5 * sub_size[:, None, :] * (1.0 + GAUSS[None])   # (m, q, 3) from the corner
    xi = 2.0 * inside / size[:, None, :] - 1.0
    d = elasticity_matrix(lam, mu)
    b = _b_matrix(_brick_gradients(xi, 0.5 * size))
    c = _thermal_load(b, d, alpha, (0.5 * sub_size).prod(axis=1))
    _, first, which = np.unique(np.column_stack([size, lam, mu]), axis=0, return_index=True, return_inverse=True)
    return _condense(_stiffness(size[first], d[first])[which.ravel()], c)[1]    # one stiffness per brick kind
