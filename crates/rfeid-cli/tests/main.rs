//! The integration tests of the command line, one module per file, built as one
//! test binary (one link instead of one per file, and the harness
//! spreads every test over the cores). Run one file's tests with
//! `cargo test --release -p rfeid-cli --test integration -- FILE::`.

// Helpers shared by the files.
mod support;

// The tests, one module per file.
mod bad_input;
mod campaign_cli;
mod design_cli;
mod free_axis_cli;
mod identify_set_start;
mod import_formats;
mod interruption;
mod joint_laws;
mod mutation;
mod outputs_and_failures;
mod report_and_output;
mod shard_files;
mod shards;
mod silverbox;
mod verdict_exit;

/// Every file of `tests/` is one of the modules above: a file without its
/// `mod` line would be compiled by nothing and its tests never run.
#[test]
fn every_test_file_is_a_module_of_this_binary() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let main = std::fs::read_to_string(dir.join("main.rs")).unwrap();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let is_helper = path.join("mod.rs").exists();
        let is_test = path.extension().is_some_and(|e| e == "rs") && stem != "main";
        if is_helper || is_test {
            assert!(
                main.contains(&format!("\nmod {stem};\n")),
                "tests/main.rs does not declare `mod {stem};`"
            );
        }
    }
}
