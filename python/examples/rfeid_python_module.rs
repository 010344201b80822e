//! The Python module `rfeid._rfeid` built as an example, so that `cargo
//! test --release --workspace` builds it with the tests' build of the
//! library; `.ci/run` runs the Python tests on it. `pip install ./python`
//! builds the same source as the package's library.
#[path = "../src/lib.rs"]
mod module;
