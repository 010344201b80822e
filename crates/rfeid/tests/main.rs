//! The integration tests of the library, one module per file, built as one
//! test binary (one link instead of one per file, and the harness
//! spreads every test over the cores). Run one file's tests with
//! `cargo test --release -p rfeid --test integration -- FILE::`.

// Helpers shared by the files.
mod coloured_cases;
mod common;
mod import_common;
mod machine_tool;
mod problems;
mod report_support;
mod wide_cases;

// The tests, one module per file.
mod aliasing_knee_column;
mod blocked_jacobian;
mod bouc_wen;
mod campaign_model_file;
mod constant_signal;
mod contact;
mod design;
mod energy_free_vibration;
mod excitation_breakpoints;
mod free_axis;
mod frf;
mod frf_coverage;
mod frf_measured;
mod friction;
mod identification_bfgs;
mod identification_campaign;
mod identification_cancel;
mod identification_coloured_noise;
mod identification_global;
mod identification_knee_column;
mod identification_lm;
mod identification_low_rate;
mod identification_plan;
mod identification_round_trip;
mod identification_scale;
mod identification_uncertainty;
mod identification_verdict;
mod identification_wide_boxes;
mod import_data_file;
mod import_mat;
mod import_no_time_axis;
mod import_robustness;
mod import_uff;
mod jacobian_by_blocks;
mod kept_runs;
mod knee_column_reference;
mod lab_data;
mod model_file_errors;
mod model_file_fuzz;
mod model_file_reading;
mod model_file_reference;
mod plan_abandoning;
mod power_law_exponent_one;
mod profiles;
mod regression_empty_wrt_sensitivities;
mod regression_power_law_padding_divergence;
mod report_knee_column;
mod report_synthetic;
mod ridge_restarts;
mod rigid_motion_invariance;
mod sdof_closed_form;
mod search_steps;
mod sensitivities;
mod sensitivity_threads;
mod shipped_data;
mod simulation_failures;
mod sparse_kernels;
mod static_equilibrium;
mod step_check;
mod stiff_pads;
mod table_signal;
mod two_body_modal;
mod workspace_reuse;

/// Every file of each crate's `tests/` (this one's and the command line's)
/// is a module of that crate's `tests/main.rs`: a file without its `mod`
/// line would be compiled by nothing and its tests never run.
#[test]
fn every_test_file_is_a_module_of_its_binary() {
    let here = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for dir in [here.join("tests"), here.join("../rfeid-cli/tests")] {
        let main = std::fs::read_to_string(dir.join("main.rs")).unwrap();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            let is_helper = path.join("mod.rs").exists();
            let is_test = path.extension().is_some_and(|e| e == "rs") && stem != "main";
            if is_helper || is_test {
                assert!(
                    main.contains(&format!("\nmod {stem};\n")),
                    "{}/main.rs does not declare `mod {stem};`",
                    dir.display()
                );
            }
        }
    }
}
