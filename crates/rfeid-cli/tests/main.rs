//! The integration tests of the command line, one module per file, built as one
//! test binary (one link instead of one per file, and the harness
//! spreads every test over the cores). Run one file's tests with
//! `cargo test --release -p rfeid-cli --test integration -- FILE::`. That
//! every file of `tests/` has its `mod` line here is checked by the
//! library's tests (`every_test_file_is_a_module_of_its_binary`).

// Helpers shared by the files.
mod support;

// The tests, one module per file.
mod bad_input;
mod campaign_cli;
mod design_cli;
mod free_axis_cli;
mod frf_cli;
mod identify_set_start;
mod import_formats;
mod interruption;
mod joint_laws;
mod mutation;
mod outputs_and_failures;
mod outside_fixes;
mod outside_help;
mod profiles_cli;
mod report_and_output;
mod shard_files;
mod shards;
mod silverbox;
mod verdict_exit;
