//! numpy arrays in and out: checked, converted, named in errors.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// `obj` as a C-contiguous numpy array (`numpy.asarray`, with `dtype` when given).
pub(crate) fn asarray<'py>(
    obj: &Bound<'py, PyAny>,
    dtype: Option<&str>,
) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    match dtype {
        Some(d) => np.call_method1("ascontiguousarray", (obj, d)),
        None => np.call_method1("ascontiguousarray", (obj,)),
    }
}

/// `obj` as a numpy array whose dtype kind (numpy's one-letter `dtype.kind`) is one of
/// `kinds`; an empty array of any dtype passes. `what` names the kinds in the error.
fn checked_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    kinds: &str,
    what: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let a = asarray(obj, None)?;
    let kind: String = a.getattr("dtype")?.getattr("kind")?.extract()?;
    let size: usize = a.getattr("size")?.extract()?;
    if size > 0 && !(kind.len() == 1 && kinds.contains(kind.as_str())) {
        return Err(PyTypeError::new_err(format!(
            "{name} must hold {what}, not dtype {}",
            a.getattr("dtype")?.str()?
        )));
    }
    Ok(a)
}

/// `obj` as rows of `N` floats: an `(n, N)` array-like of numbers (any real dtype).
pub(crate) fn float_rows<const N: usize>(
    obj: &Bound<'_, PyAny>,
    name: &str,
) -> PyResult<Vec<[f64; N]>> {
    let a = checked_array(obj, name, "fiu", "real numbers")?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    let a = if shape == [0] {
        a.call_method1("reshape", (0, N))?
    } else {
        a
    };
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != N {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (n, {N}), not {shape:?}"
        )));
    }
    let a = asarray(&a, Some("float64"))?;
    let a: PyReadonlyArray2<'_, f64> = a.extract()?;
    let flat = a.as_slice()?;
    let rows: Vec<[f64; N]> = flat
        .chunks_exact(N)
        .map(|c| std::array::from_fn(|k| c[k]))
        .collect();
    if let Some(i) = flat.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{name}[{}] has a value that is not finite ({})",
            i / N,
            flat[i]
        )));
    }
    Ok(rows)
}

/// `obj` as an array of real numbers of any shape (any real dtype): its shape and its
/// values in row-major order, every one finite.
pub(crate) fn float_grid(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let a = checked_array(obj, name, "fiu", "real numbers")?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    let a = asarray(&a.call_method0("ravel")?, Some("float64"))?;
    let a: PyReadonlyArray1<'_, f64> = a.extract()?;
    let values = a.as_slice()?.to_vec();
    if let Some(i) = values.iter().position(|x| !x.is_finite()) {
        // The index of the first row (all axes but the last) holding the value.
        let mut rest = i / shape.last().copied().unwrap_or(1).max(1);
        let mut at = Vec::new();
        for &n in shape.iter().rev().skip(1) {
            at.push(rest % n.max(1));
            rest /= n.max(1);
        }
        at.reverse();
        let at: Vec<String> = at.iter().map(ToString::to_string).collect();
        return Err(PyValueError::new_err(format!(
            "{name}[{}] has a value that is not finite ({})",
            at.join(", "),
            values[i]
        )));
    }
    Ok((shape, values))
}

/// `obj` as a flat array of floats (any real dtype, any shape flattened).
pub(crate) fn float_array(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let a = checked_array(obj, name, "fiu", "real numbers")?;
    let a = asarray(&a.call_method0("ravel")?, Some("float64"))?;
    let a: PyReadonlyArray1<'_, f64> = a.extract()?;
    Ok(a.as_slice()?.to_vec())
}

/// `obj` as a flat array of indices (integers from 0 to `u32::MAX - 1`; any integer dtype).
pub(crate) fn index_array(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<u32>> {
    let a = checked_array(obj, name, "iu", "integers")?;
    let a = asarray(&a.call_method0("ravel")?, Some("int64"))?;
    let a: PyReadonlyArray1<'_, i64> = a.extract()?;
    a.as_slice()?
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            u32::try_from(x)
                .ok()
                .filter(|&x| x != u32::MAX)
                .ok_or_else(|| {
                    PyValueError::new_err(format!("{name}[{i}] = {x} is not a valid index"))
                })
        })
        .collect()
}

/// `read` of an optional argument: `None` when it is absent or Python's `None`.
pub(crate) fn optional<T>(
    obj: Option<&Bound<'_, PyAny>>,
    read: impl FnOnce(&Bound<'_, PyAny>) -> PyResult<T>,
) -> PyResult<Option<T>> {
    match obj {
        Some(o) if !o.is_none() => read(o).map(Some),
        _ => Ok(None),
    }
}

/// `rows` as an `(n, N)` float64 array (the vector's buffer handed to numpy, reshaped).
pub(crate) fn rows_to_py<'py, const N: usize>(
    py: Python<'py>,
    rows: &[[f64; N]],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows.len(), N])?
        .into_any())
}

/// `v` as a float64 array.
pub(crate) fn floats_to_py<'py>(
    py: Python<'py>,
    v: impl Iterator<Item = f64>,
) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v.collect()).into_any()
}

/// `v` as an int32 array (indices of meshes subsurf accepts fit).
pub(crate) fn indices_to_py<'py>(
    py: Python<'py>,
    v: impl Iterator<Item = u32>,
) -> Bound<'py, PyAny> {
    let v: Vec<i32> = v.map(|x| x as i32).collect();
    PyArray1::from_vec(py, v).into_any()
}
