//! The Python module `rfeid._rfeid`: a thin layer over the library, which
//! the package `rfeid` (python/rfeid) wraps in numpy and pandas. Every step
//! of a run is the library's, as on the command line
//! ([`rfeid::identification::options`], [`rfeid::model::set_values`],
//! [`rfeid::measurement::simulated`], [`rfeid::report::at_estimate`]), so
//! the same inputs and options give the same numbers bit for bit.
//!
//! Arrays cross as little-endian `f64` bytes, which numpy reads without a
//! copy per element (`numpy.frombuffer`).
mod data;
mod design;
mod errors;
mod model;
mod result;
mod run;
mod shards;
mod validate;
mod watch;

use pyo3::prelude::*;

/// The native part of rfeid (Rust, PyO3); use the package `rfeid`. Arrays
/// cross as little-endian float64 bytes; every number is SI.
#[pymodule]
fn _rfeid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ModelError", py.get_type::<errors::ModelError>())?;
    m.add("DataError", py.get_type::<errors::DataError>())?;
    m.add(
        "IdentificationError",
        py.get_type::<errors::IdentificationError>(),
    )?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<result::PyIdentification>()?;
    m.add_class::<design::PyDesign>()?;
    m.add_function(wrap_pyfunction!(run::identify, m)?)?;
    m.add_function(wrap_pyfunction!(run::search_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(design::design, m)?)?;
    m.add_function(wrap_pyfunction!(validate::validate, m)?)?;
    m.add_function(wrap_pyfunction!(shards::identify_shard, m)?)?;
    m.add_function(wrap_pyfunction!(shards::merge, m)?)?;
    m.add_function(wrap_pyfunction!(validate::load_result, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
