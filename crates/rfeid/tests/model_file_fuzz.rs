//! A seeded fuzz loop over campaign model files: 10⁴ mutations of
//! `examples/knee-column-campaign/model.toml` (lines deleted, duplicated or
//! swapped, values replaced by tokens of every TOML type and absurd sizes,
//! tables turned into single tables or other kinds, the text cut or a
//! character spliced in) are parsed as `rfeid` parses them. None may panic,
//! and every refusal must name the file and point into it: the entry, the
//! field, or the offending text's span.
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rfeid::io::model_file::parse_model;
use std::path::{Path, PathBuf};

fn campaign() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column-campaign/model.toml")
}

/// Values of every TOML type, with units, signs and sizes users get wrong.
const TOKENS: [&str; 18] = [
    "\"\"",
    "-1",
    "0",
    "1e400",
    "nan",
    "inf",
    "\"x\"",
    "[]",
    "{}",
    "\"20,5 N\"",
    "\"1 kg\"",
    "\"-1 daN\"",
    "true",
    "18446744073709551615",
    "[[1]]",
    "[0.0, 0.0]",
    "{ law = \"power\" }",
    "\"1e9 m\"",
];

/// The headers a table may be turned into.
const HEADERS: [&str; 8] = [
    "[experiment]",
    "[[experiment]]",
    "[[body]]",
    "[[element]]",
    "[[parameter]]",
    "[[sensor]]",
    "[[excitation]]",
    "[simulation]",
];

/// One random edit of the file's lines.
fn mutate(lines: &mut Vec<String>, rng: &mut ChaCha8Rng) {
    if lines.is_empty() {
        return;
    }
    let i = rng.random_range(0..lines.len());
    match rng.random_range(0..6) {
        0 => {
            lines.remove(i);
        }
        1 => {
            let l = lines[i].clone();
            lines.insert(i, l);
        }
        2 => {
            let j = rng.random_range(0..lines.len());
            lines.swap(i, j);
        }
        3 | 4 => {
            // A value replaced: the line's first `key = …` keeps its key.
            if let Some((key, _)) = lines[i].split_once('=') {
                let token = TOKENS[rng.random_range(0..TOKENS.len())];
                lines[i] = format!("{key}= {token}");
            }
        }
        _ => {
            if lines[i].starts_with('[') {
                lines[i] = HEADERS[rng.random_range(0..HEADERS.len())].into();
            }
        }
    }
}

/// The text, sometimes cut short or with a character spliced in.
fn text_of(lines: &[String], rng: &mut ChaCha8Rng) -> String {
    let text = lines.join("\n");
    if text.is_empty() {
        return text;
    }
    match rng.random_range(0..10) {
        0 => {
            let cut = rng.random_range(0..text.len());
            let cut = (0..=cut).rev().find(|&c| text.is_char_boundary(c)).unwrap();
            text[..cut].to_string()
        }
        1 => {
            let at = rng.random_range(0..text.len());
            let at = (0..=at).rev().find(|&c| text.is_char_boundary(c)).unwrap();
            let junk = ["]", "[", "\"", "=", "\u{feff}", "ü", "\0", "{"][rng.random_range(0..8)];
            format!("{}{junk}{}", &text[..at], &text[at..])
        }
        _ => text,
    }
}

#[test]
fn ten_thousand_mutated_campaign_files_are_refused_with_a_place_or_accepted() {
    let path = campaign();
    let original = std::fs::read_to_string(&path).unwrap();
    parse_model(&original, &path).expect("the campaign example parses");
    let base: Vec<String> = original.lines().map(String::from).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(25);
    let (mut refused, mut accepted) = (0, 0);
    for case in 0..10_000 {
        let mut lines = base.clone();
        for _ in 0..=rng.random_range(0..3) {
            mutate(&mut lines, &mut rng);
        }
        let text = text_of(&lines, &mut rng);
        let outcome = std::panic::catch_unwind(|| parse_model(&text, &path).map_err(Box::new));
        let Ok(result) = outcome else {
            panic!("case {case} panicked on:\n{text}");
        };
        match result {
            Ok(_) => accepted += 1,
            Err(e) => {
                assert_eq!(e.path, path, "case {case}");
                let placed = !e.entry.is_empty() || !e.field.is_empty() || e.span.is_some();
                assert!(placed, "case {case}: {e} names no place in:\n{text}");
                assert!(e.to_string().contains("model.toml"), "case {case}: {e}");
                refused += 1;
            }
        }
    }
    eprintln!("model-file fuzz: {refused} refused, {accepted} accepted of 10000");
    assert!(
        refused > 1000 && accepted > 100,
        "{refused} refused, {accepted} accepted"
    );
}
