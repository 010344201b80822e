//! Wide-box identification cases (issue 8 §2), tabulated: for each example
//! model, box width factor and noise seed, the largest |estimate − truth|
//! in standard errors, the verdict and the wall time of the identification.
//!
//! ```sh
//! cargo run --release -p rfeid --example wide_boxes -- [--seeds 5] [--first-seed 1] [--noise 0.01] [--factors 10,100] [--equal-weights] [--from-truth] [MODEL...]
//! ```
//!
//! MODEL names a directory under `examples/` (default: all of
//! `knee-column`, `lathe`, `tailstock`). The cases are those of
//! `tests/wide_cases` (the truth at a seeded random log position 15–85 %
//! of each box), identified at `rfeid identify`'s default settings;
//! `--equal-weights` weights the sensors equally instead, `--from-truth`
//! runs one local search from the true values instead of the plan,
//! `--write DIR` also writes each case as DIR/MODEL-fFACTOR-sSEED/ with
//! `model.toml` (the boxes in SI) and `data.csv`, for
//! `rfeid identify DIR/…/model.toml --data DIR/…/data.csv -o r.json --timings`.
#[path = "../tests/wide_cases/mod.rs"]
mod wide_cases;

use rfeid::identification::warning::Warning;
use std::time::Instant;
use wide_cases::{data, default_settings, example, run, widened, widened_text, worst_z, MODELS};

fn main() {
    let mut seeds = 5u64;
    let mut first_seed = 1u64;
    let mut noise = 0.01;
    let mut factors = vec![10.0, 100.0];
    let mut models: Vec<String> = Vec::new();
    let mut from_truth = false;
    let mut equal = false;
    let mut write: Option<std::path::PathBuf> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the option");
        match a.as_str() {
            "--seeds" => seeds = value().parse().expect("a count"),
            "--first-seed" => first_seed = value().parse().expect("a seed"),
            "--from-truth" => from_truth = true,
            "--equal-weights" => equal = true,
            "--write" => write = Some(std::path::PathBuf::from(value())),
            "--noise" => noise = value().parse().expect("a fraction"),
            "--factors" => {
                factors = value()
                    .split(',')
                    .map(|f| f.parse().expect("a factor"))
                    .collect()
            }
            _ => models.push(a),
        }
    }
    if models.is_empty() {
        models = MODELS.iter().map(|m| m.to_string()).collect();
    }
    let mut settings = default_settings();
    if equal {
        // `--weights equal`, the paper's (eq. 14).
        settings.weighting = rfeid::identification::pipeline::Weighting::Equal;
    }
    if from_truth {
        // One local search from the true values (the models' `value`s): the
        // minimum nearest the truth, to compare J with.
        settings.start = rfeid::identification::pipeline::Start::Values;
    }
    println!("model        factor seed  worst z  (parameter)  verdict      wall s  J             restarted");
    let (mut cases, mut within) = (0, 0);
    for name in &models {
        for &factor in &factors {
            for seed in first_seed..first_seed + seeds {
                let model = widened(&example(name), factor, seed);
                let y = data(&model, noise, seed);
                if let Some(dir) = &write {
                    // The case as files, for `rfeid identify --timings`.
                    let case = dir.join(format!("{name}-f{factor}-s{seed}"));
                    std::fs::create_dir_all(&case).expect("the case directory");
                    let source = example(name);
                    let text = widened_text(&source, &model);
                    std::fs::write(case.join("model.toml"), text).expect("model written");
                    for f in &model.files {
                        let to = case.join(f.file_name().expect("a file name"));
                        std::fs::copy(f, to).expect("signal table copied");
                    }
                    let mut csv = Vec::new();
                    let series = rfeid::measurement::to_timeseries(&model, &y);
                    rfeid::io::timeseries::write_csv_to(&mut csv, &series).expect("CSV");
                    std::fs::write(case.join("data.csv"), csv).expect("data written");
                }
                let t = Instant::now();
                let r = run(&model, y, &settings);
                let wall = t.elapsed().as_secs_f64();
                let (z, worst) = worst_z(&r);
                let verdict = match r.verdict.as_ref().map(|v| v.trustworthy) {
                    Some(true) => "trustworthy",
                    Some(false) => "suspect",
                    None => "none",
                };
                // The automatic restarts, if any ran.
                let restarted = r.warnings.iter().find_map(|w| match w {
                    Warning::SideMinimum { restarts, .. } => Some(restarts.to_string()),
                    _ => None,
                });
                cases += 1;
                within += usize::from(z <= 3.0);
                println!(
                    "{name:<12} {factor:>6} {seed:>4} {z:>8.2}  ({worst:<9})  {verdict:<12} {wall:>6.2}  {:.6e}  {}",
                    r.criterion,
                    restarted.unwrap_or_default()
                );
            }
        }
    }
    println!("{within} of {cases} cases with every estimate within 3 standard errors");
}
