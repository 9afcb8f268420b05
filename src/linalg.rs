//! Small dense linear-algebra helpers shared by every method: checks of user matrices,
//! symmetric square roots, and the conversions between JSON rows and nalgebra matrices.

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// Relative tolerance for symmetry and semidefiniteness checks of user matrices.
pub const SYM_TOL: f64 = 1e-9;

/// Build a matrix from JSON rows (`[[a, b], [c, d]]`), checking that the rows have equal length
/// and that every entry is finite.
pub fn from_rows(field: &str, rows: &[Vec<f64>]) -> Result<DMatrix<f64>> {
    if rows.is_empty() || rows[0].is_empty() {
        return Err(Error::field(
            field,
            "must be a non-empty matrix (a list of rows)",
        ));
    }
    let cols = rows[0].len();
    for (i, r) in rows.iter().enumerate() {
        if r.len() != cols {
            return Err(Error::field(
                field,
                format!(
                    // Rows and columns counted from 1, as the page's matrix boxes and the CSV
                    // reader count them.
                    "has rows of different lengths (row 1 has {cols}, row {} has {})",
                    i + 1,
                    r.len()
                ),
            ));
        }
        if let Some(j) = r.iter().position(|v| !v.is_finite()) {
            return Err(Error::field(
                field,
                format!("has a non-finite entry at row {}, column {}", i + 1, j + 1),
            ));
        }
    }
    Ok(DMatrix::from_fn(rows.len(), cols, |i, j| rows[i][j]))
}

/// Sort numbers increasingly (by `f64::total_cmp`). Every sort of plain numbers in the crate
/// goes through here, [`sort_decreasing`] or [`decreasing_order`]: each distinct comparison
/// closure would be another copy of the standard library's sort in the wasm module (~5 KB).
/// Numbers equal under `total_cmp` are the same bits, so the unstable sort is exact.
pub fn sort_increasing(v: &mut [f64]) {
    v.sort_unstable_by(f64::total_cmp);
}

/// Sort numbers decreasingly (singular values).
pub fn sort_decreasing(v: &mut [f64]) {
    sort_increasing(v);
    v.reverse();
}

/// The indices of `values` by decreasing value, equal values in index order: the order in
/// which to take singular vectors.
pub fn decreasing_order(values: &[f64]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..values.len()).collect();
    idx.sort_by(|&i, &j| values[j].total_cmp(&values[i]));
    idx
}

/// `f` of the entries of `a` and `b` pair by pair (as far as the shorter goes).
pub fn zip_with(a: &[f64], b: &[f64], f: fn(f64, f64) -> f64) -> Vec<f64> {
    a.iter().zip(b).map(|(&x, &y)| f(x, y)).collect()
}

/// Rows of a matrix, for JSON.
pub fn to_rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// A vector from JSON, checking length and finiteness.
pub fn vector(field: &str, v: &[f64], len: usize) -> Result<DVector<f64>> {
    if v.len() != len {
        return Err(Error::field(
            field,
            format!(
                "must have {len_entries}, found {}",
                v.len(),
                len_entries = crate::error::counted(len, "entry", "entries")
            ),
        ));
    }
    if let Some(j) = v.iter().position(|x| !x.is_finite()) {
        return Err(Error::field(
            field,
            format!("has a non-finite entry at position {j}"),
        ));
    }
    Ok(DVector::from_column_slice(v))
}

/// Check that `m` is `rows × cols`.
pub fn expect_shape(field: &str, m: &DMatrix<f64>, rows: usize, cols: usize) -> Result<()> {
    if m.nrows() != rows || m.ncols() != cols {
        return Err(Error::field(
            field,
            format!("must be {rows}×{cols}, found {}×{}", m.nrows(), m.ncols()),
        ));
    }
    Ok(())
}

fn scale(m: &DMatrix<f64>) -> f64 {
    m.amax().max(f64::MIN_POSITIVE)
}

/// Sweeps any one decomposition may take: nalgebra's default (0) loops until convergence,
/// which a matrix holding ±∞ never reaches.
const MAX_SWEEPS: usize = 10_000;

/// The SVD of `m`, or `None` when `m` holds a NaN or ±∞ (nalgebra panics with "Singular value
/// was NaN" or never converges on those) or it does not converge within `MAX_SWEEPS`. Every
/// SVD of the core goes through here or checks finiteness first.
pub fn try_svd(
    m: DMatrix<f64>,
    compute_u: bool,
    compute_v: bool,
) -> Option<nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    m.try_svd(compute_u, compute_v, f64::EPSILON, MAX_SWEEPS)
}

/// The eigendecomposition of a symmetric `m`, with the same guarantees as [`try_svd`].
pub fn try_symmetric_eigen(
    m: DMatrix<f64>,
) -> Option<nalgebra::SymmetricEigen<f64, nalgebra::Dyn>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    nalgebra::SymmetricEigen::try_new(m, f64::EPSILON, MAX_SWEEPS)
}

/// Smallest eigenvalue of a symmetric matrix; NaN when it has none (a non-finite entry).
pub fn min_eigenvalue(m: &DMatrix<f64>) -> f64 {
    try_symmetric_eigen(m.clone()).map_or(f64::NAN, |e| e.eigenvalues.min())
}

/// Check that a covariance is symmetric and positive semidefinite (`definite = false`) or
/// positive definite (`definite = true`), relative to its largest entry.
pub fn check_covariance(field: &str, m: &DMatrix<f64>, definite: bool) -> Result<()> {
    let kind = if definite {
        "positive definite"
    } else {
        "positive semidefinite"
    };
    if !m.is_square() {
        return Err(Error::field(
            field,
            format!("must be square, found {}×{}", m.nrows(), m.ncols()),
        ));
    }
    // Every tolerance is relative to the largest entry s: rounding of a computed covariance
    // is of that size, and a definite matrix whose smallest eigenvalue is below 10⁻⁹·s is
    // singular to the precision the methods invert it with.
    let s = scale(m);
    let diff = m - m.transpose();
    let asym = diff.amax();
    if asym > SYM_TOL * s {
        let (i, j) = diff.iamax_full();
        return Err(Error::field(
            field,
            format!(
                "must be symmetric {kind}: {field}[{i}][{j}] and {field}[{j}][{i}] differ by {asym:.3e} (the largest asymmetry), more than 1e-9 × its largest entry ({s:.3e})"
            ),
        ));
    }
    let lmin = min_eigenvalue(m);
    if !lmin.is_finite() {
        return Err(Error::field(
            field,
            "must be a finite symmetric matrix (an entry is not a finite number)",
        ));
    }
    let floor = SYM_TOL * s;
    if definite && lmin <= floor {
        return Err(Error::field(
            field,
            if lmin < -floor {
                format!("must be symmetric positive definite: its smallest eigenvalue is {lmin:.3e}, negative")
            } else {
                format!(
                    "must be symmetric positive definite: its smallest eigenvalue {lmin:.2e} is not above 1e-9 × its largest entry ({s:.2e}), so it is numerically singular; give it a smallest eigenvalue above {floor:.2e}"
                )
            },
        ));
    }
    if !definite && lmin < -floor {
        return Err(Error::field(
            field,
            format!(
                "must be symmetric positive semidefinite: its smallest eigenvalue is {lmin:.3e}, below the rounding allowed, −1e-9 × its largest entry ({s:.3e})"
            ),
        ));
    }
    Ok(())
}

/// (m + mᵀ)/2: removes the rounding asymmetry that products like F P Fᵀ accumulate.
pub fn symmetrize(m: &DMatrix<f64>) -> DMatrix<f64> {
    (m + m.transpose()) * 0.5
}

/// Lower-triangular L with L Lᵀ = m for a symmetric positive *semi*definite m (eigenvalues
/// clipped at zero, then a QR makes the factor triangular). Used to draw Gaussian noise whose
/// covariance may be singular, e.g. the backward noise V^b_2 = 0 when x_1 is known.
pub fn psd_sqrt(m: &DMatrix<f64>) -> DMatrix<f64> {
    let n = m.nrows();
    if let Some(c) = symmetrize(m).cholesky() {
        return c.l();
    }
    // No factor of a matrix with a non-finite entry: NaNs, which the report check names.
    let Some(eig) = try_symmetric_eigen(symmetrize(m)) else {
        return DMatrix::from_element(n, n, f64::NAN);
    };
    let mut root = eig.eigenvectors.clone();
    for j in 0..n {
        let s = eig.eigenvalues[j].max(0.0).sqrt();
        root.column_mut(j).scale_mut(s);
    }
    // root rootᵀ = m; make it lower triangular: rootᵀ = Q R  ⇒  root = Rᵀ Qᵀ, and Rᵀ Rᵀᵀ = m.
    let r = root.transpose().qr().r();
    let mut l = r.transpose();
    for j in 0..n {
        if l[(j, j)] < 0.0 {
            l.column_mut(j).neg_mut();
        }
    }
    l
}

/// Inverse of a square matrix, or an error naming what was being inverted.
pub fn inverse(what: &str, m: &DMatrix<f64>) -> Result<DMatrix<f64>> {
    let inv = m
        .clone()
        .try_inverse()
        .filter(|i| i.iter().all(|v| v.is_finite()));
    inv.ok_or_else(|| Error::field(what, "is singular"))
}

/// Reciprocal condition number estimate σ_min/σ_max (0 for a singular matrix).
pub fn rcond(m: &DMatrix<f64>) -> f64 {
    let sv = m.clone().singular_values();
    let max = sv.max();
    if max == 0.0 {
        0.0
    } else {
        sv.min() / max
    }
}

/// Inverse and reciprocal 1-norm condition number 1/(‖m‖₁‖m⁻¹‖₁) (LU, no SVD), or `None`
/// when m is singular in floating point.
pub fn inverse_rcond(m: &DMatrix<f64>) -> Option<(DMatrix<f64>, f64)> {
    let inv = m
        .clone()
        .try_inverse()
        .filter(|i| i.iter().all(|v| v.is_finite()))?;
    let rc = 1.0 / (norm_1(m) * norm_1(&inv));
    Some((inv, rc))
}

/// Induced l1 operator norm ‖m‖₁: the largest absolute column sum.
pub fn norm_1(m: &DMatrix<f64>) -> f64 {
    m.column_iter()
        .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Induced l∞ operator norm ‖m‖∞: the largest absolute row sum (Tempo's Theorems 4 and 5 use
/// it, consistent with the boxes of an l∞ state norm).
pub fn norm_inf(m: &DMatrix<f64>) -> f64 {
    m.row_iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Induced l2 operator norm ‖m‖₂ (spectral norm, the largest singular value; 0 for an empty
/// matrix, +∞ when an entry is not finite, where an SVD would not converge).
pub fn norm_2(m: &DMatrix<f64>) -> f64 {
    if m.is_empty() {
        return 0.0;
    }
    if !m.iter().all(|v| v.is_finite()) {
        return f64::INFINITY;
    }
    try_svd(m.clone(), false, false).map_or(f64::INFINITY, |s| s.singular_values.max())
}

/// The eigenvalues of a square `m` as (re, im), largest modulus first, from its real Schur form
/// with the iteration cap of [`try_svd`]; `None` when `m` holds a NaN or ±∞ or does not converge.
pub fn try_eigenvalues(m: &DMatrix<f64>) -> Option<Vec<[f64; 2]>> {
    if !m.is_square() || !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let schur = nalgebra::linalg::Schur::try_new(m.clone(), f64::EPSILON, MAX_SWEEPS)?;
    let mut e: Vec<[f64; 2]> = schur
        .complex_eigenvalues()
        .iter()
        .map(|c| [c.re, c.im])
        .collect();
    e.sort_by(|a, b| {
        b[0].hypot(b[1])
            .total_cmp(&a[0].hypot(a[1]))
            .then(b[1].total_cmp(&a[1]))
    });
    Some(e)
}

/// Spectral radius via the eigenvalues of the (real) Schur form.
pub fn spectral_radius(m: &DMatrix<f64>) -> f64 {
    m.clone()
        .complex_eigenvalues()
        .iter()
        .map(|c| c.norm())
        .fold(0.0, f64::max)
}

/// Select rows and columns `idx` of a square matrix.
pub fn sub_matrix(m: &DMatrix<f64>, idx: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(idx.len(), idx.len(), |i, j| m[(idx[i], idx[j])])
}

/// Select entries `idx` of a vector.
pub fn sub_vector(v: &DVector<f64>, idx: &[usize]) -> DVector<f64> {
    DVector::from_fn(idx.len(), |i, _| v[idx[i]])
}
