//! The layer the commands are thin over: an identification run in stages,
//! with values passed between them. Each file holds one concern:
//!
//! - inputs: [`inputs`] (a model and its data, `--set`, `--tolerance` /
//!   `--substeps`), [`experiments`] (a campaign's data), [`demo_case`] (the
//!   built-in benchmark), [`shard_arg`] (`--shard K/N`; the shard files are the
//!   library's `io::shard_file`);
//! - search set-up: [`limits`], [`search`], [`progress`];
//! - a result of this model: [`belongs`];
//! - inputs unchanged: [`digest`] (what RESULT.json records of its files);
//! - failures: [`failures`] (library errors as exit statuses);
//! - designs: [`design_text`] (the table and JSON of `rfeid design`);
//! - results: [`show`], [`profile_text`] and [`verdict_text`] (the tables
//!   and notes),
//!   [`report`] (report files), [`closing`] (the closing sequence of
//!   `identify`, `demo` and `merge`).
pub mod belongs;
pub mod closing;
pub mod demo_case;
pub mod design_text;
pub mod digest;
pub mod experiments;
pub mod failures;
pub mod inputs;
pub mod limits;
pub mod profile_text;
pub mod progress;
pub mod report;
pub mod search;
pub mod shard_arg;
pub mod show;
pub mod verdict_text;
