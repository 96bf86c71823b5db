//! Rust values to Python: JSON documents (the reports of `flexmbd … --json`) to dicts and
//! lists, vectors and matrices to NumPy arrays.

use faer::Mat;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

/// A JSON value as Python: None, bool, int, float, str, list, dict.
pub fn json(py: Python<'_>, v: &Value) -> PyResult<Py<PyAny>> {
    Ok(match v {
        Value::Null => py.None(),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any().unbind()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any().unbind()
            } else {
                n.as_f64()
                    .unwrap_or(f64::NAN)
                    .into_pyobject(py)?
                    .into_any()
                    .unbind()
            }
        }
        Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| json(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any().unbind()
        }
        Value::Object(o) => {
            let d = PyDict::new(py);
            for (k, x) in o {
                d.set_item(k, json(py, x)?)?;
            }
            d.into_any().unbind()
        }
    })
}

/// A vector as a 1-D array.
pub fn vec1(py: Python<'_>, v: Vec<f64>) -> Py<PyAny> {
    PyArray1::from_vec(py, v).into_any().unbind()
}

/// Row-major data as an array of `shape`.
pub fn array(py: Python<'_>, data: Vec<f64>, shape: &[usize]) -> PyResult<Py<PyAny>> {
    Ok(PyArray1::from_vec(py, data)
        .reshape(shape.to_vec())?
        .into_any()
        .unbind())
}

/// A matrix as a 2-D array.
pub fn mat(py: Python<'_>, m: &Mat<f64>) -> PyResult<Py<PyAny>> {
    let (r, c) = (m.nrows(), m.ncols());
    let mut data = Vec::with_capacity(r * c);
    for i in 0..r {
        for j in 0..c {
            data.push(m[(i, j)]);
        }
    }
    array(py, data, &[r, c])
}

/// Any array-like of numbers (any memory layout, byte order, alignment or dtype; arrays from
/// other processes can be misaligned) as a vector of f64: NumPy copies it to a contiguous,
/// aligned float64 array first where it is not one already.
pub fn f64_vector(obj: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let a = np.call_method1(
        "require",
        (
            np.call_method1("asarray", (obj, "float64"))?,
            "float64",
            vec!["C", "A"],
        ),
    )?;
    let flat = a.call_method0("ravel")?;
    let arr: numpy::PyReadonlyArray1<'_, f64> = flat.extract()?;
    Ok(arr.as_slice()?.to_vec())
}
