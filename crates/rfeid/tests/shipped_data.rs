//! The data shipped in the repository's `data/` (data/README.md) against
//! their originals, to the last bit, where the originals are at hand
//! (`../shared` beside the clone, as the project's CI has it): the
//! Silverbox MAT-file and the Sobol reference byte for byte, the Bouc–Wen
//! records' MAT-files value for value against the published CSVs.
use rfeid::io::mat::read_mat_vectors;
use rfeid::io::timeseries::read_csv;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The originals' directory, or `None` (with a note) on a clone alone.
fn shared() -> Option<PathBuf> {
    let dir = repo().join("../shared");
    if dir.join("data").is_dir() {
        Some(dir)
    } else {
        eprintln!("no ../shared beside the clone: the shipped data are not compared");
        None
    }
}

#[test]
fn copied_files_are_the_originals_byte_for_byte() {
    let Some(shared) = shared() else { return };
    for (ours, theirs) in [
        ("data/silverbox/SNLS80mV.mat", "data/silverbox/SNLS80mV.mat"),
        (
            "data/sobol/sobol_joe_kuo_natural_d20_n1024.csv",
            "testdata/sobol_joe_kuo_natural_d20_n1024.csv",
        ),
    ] {
        let a = std::fs::read(repo().join(ours)).unwrap();
        let b = std::fs::read(shared.join(theirs)).unwrap();
        assert!(a == b, "{ours} differs from ../shared/{theirs}");
    }
}

#[test]
fn bouc_wen_records_hold_the_published_values_bit_for_bit() {
    let Some(shared) = shared() else { return };
    for name in ["train", "test_multisine", "test_sinesweep"] {
        let mat = read_mat_vectors(&repo().join(format!("data/bouc-wen/{name}.mat"))).unwrap();
        let csv = read_csv(&shared.join(format!("data/bouc-wen/{name}.csv"))).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(mat.require_vector("time").unwrap()),
            bits(&csv.time),
            "{name}: time"
        );
        for column in ["u", "y"] {
            let published = csv.column(column).unwrap();
            assert_eq!(published.len(), csv.time.len());
            assert_eq!(
                bits(mat.require_vector(column).unwrap()),
                bits(published),
                "{name}: {column}"
            );
        }
    }
}
