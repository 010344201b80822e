//! A seeded fuzz loop over shard files: 10⁴ mutations of a valid shard
//! (fields set to values of every JSON type and absurd sizes, fields
//! deleted, points duplicated or dropped, the text cut or spliced) are
//! parsed as `merge` parses them. None may panic, and every refusal must
//! be a [`super::shard_file::ShardError`] (bad input: exit status 2 on the
//! command line) naming the file and the field, or the line and column of
//! JSON that does not parse.
use super::shard_file::{parse_shard, PointRecord, SearchSpec, ShardFile, FORMAT};
use crate::identification::options::SearchOptions;
use crate::identification::pipeline::Weighting;
use serde_json::Value;
use std::path::Path;

/// SplitMix64: a few lines of seeded randomness, enough for a fuzz loop.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Shard 1 of 3 of a 10-point plan, complete, one point failed.
fn valid() -> ShardFile {
    ShardFile {
        format: FORMAT.into(),
        hash: "0123456789abcdef".into(),
        shard: 1,
        of: 3,
        search: SearchSpec {
            options: SearchOptions {
                plan: 10,
                starts: 2,
                weights: Some(Weighting::EstimatedNoise),
                window: Some(0.15),
                ..SearchOptions::default()
            },
            tolerance: Some(1e-7),
            substeps: None,
        },
        model: "model.toml".into(),
        data: "data.csv".into(),
        seconds: 1.5,
        complete: true,
        points: [1, 4, 7]
            .into_iter()
            .map(|index| PointRecord {
                index,
                cost: (index != 4).then_some(0.25 * index as f64),
                failure: (index == 4).then(|| "the simulation diverged".into()),
                reach: Some(0.125 * index as f64),
            })
            .collect(),
    }
}

/// Values of every JSON type, with the sizes and signs that broke `merge`.
fn value(rng: &mut Rng) -> Value {
    match rng.below(14) {
        0 => Value::Null,
        1 => Value::Bool(rng.below(2) == 1),
        2 => Value::from(u64::MAX),
        3 => Value::from(1u64 << 40),
        4 => Value::from(1_000_001u64),
        5 => Value::from(-1i64),
        6 => Value::from(1e308),
        7 => Value::from(-0.5),
        8 => Value::from(rng.below(12) as u64),
        9 => Value::from("x"),
        10 => Value::from(""),
        11 => Value::Array(vec![Value::from(1)]),
        12 => serde_json::json!({ "index": 1 }),
        _ => Value::from(rng.below(1000) as f64 / 7.0),
    }
}

/// The paths a mutation may touch.
const FIELDS: [&str; 17] = [
    "format",
    "hash",
    "shard",
    "of",
    "seconds",
    "complete",
    "model",
    "data",
    "points",
    "search",
    "search/plan",
    "search/starts",
    "search/method",
    "search/weights",
    "search/noise_model",
    "search/from",
    "search/window",
];

/// One random edit of the JSON document `v`.
fn mutate(v: &mut Value, rng: &mut Rng) {
    let points = v["points"].as_array().map_or(0, Vec::len);
    match rng.below(6) {
        0 | 1 => {
            let path = FIELDS[rng.below(FIELDS.len())];
            if let Some(slot) = v.pointer_mut(&format!("/{path}")) {
                *slot = value(rng);
            }
        }
        2 => {
            let path = FIELDS[rng.below(FIELDS.len())];
            let (parent, key) = path.rsplit_once('/').unwrap_or(("", path));
            if let Some(Value::Object(o)) = v.pointer_mut(&format!("/{parent}").replace("//", "/"))
            {
                o.remove(key);
            } else if let Value::Object(o) = v {
                o.remove(key);
            }
        }
        3 if points > 0 => {
            let i = rng.below(points);
            let field = ["index", "cost", "failure"][rng.below(3)];
            let new = value(rng);
            if let Some(Value::Object(o)) = v["points"].get_mut(i) {
                o.insert(field.into(), new);
            }
        }
        4 if points > 0 => {
            let list = v["points"].as_array_mut().unwrap();
            match rng.below(2) {
                0 => {
                    let p = list[rng.below(points)].clone();
                    list.push(p);
                }
                _ => {
                    list.remove(rng.below(points));
                }
            }
        }
        _ => {
            if let Some(Value::Object(o)) = v["points"].get_mut(0) {
                o.insert("extra".into(), value(rng));
            }
        }
    }
}

/// The document's text, sometimes cut short or with a byte spliced in.
fn text_of(v: &Value, rng: &mut Rng) -> String {
    let text = serde_json::to_string_pretty(v).unwrap();
    match rng.below(10) {
        0 => {
            let cut = rng.below(text.len());
            text.char_indices()
                .take_while(|(i, _)| *i < cut)
                .map(|(_, c)| c)
                .collect()
        }
        1 => {
            let at = rng.below(text.len());
            let at = (0..=at)
                .rev()
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(0);
            let junk = ["}", "{", "\"", ",", "\u{feff}", "ü", "\0"][rng.below(7)];
            format!("{}{junk}{}", &text[..at], &text[at..])
        }
        _ => text,
    }
}

#[test]
fn ten_thousand_mutated_shard_files_are_refused_by_field_or_accepted() {
    let path = Path::new("fuzz/shard-7.json");
    let base = serde_json::to_value(valid()).unwrap();
    assert!(parse_shard(&base.to_string(), path).is_ok());
    let mut rng = Rng(0x5eed_0025);
    let (mut refused, mut accepted) = (0, 0);
    for case in 0..10_000 {
        let mut v = base.clone();
        for _ in 0..=rng.below(3) {
            mutate(&mut v, &mut rng);
        }
        let text = text_of(&v, &mut rng);
        let outcome = std::panic::catch_unwind(|| parse_shard(&text, path));
        let Ok(result) = outcome else {
            panic!("case {case} panicked on:\n{text}");
        };
        match result {
            Ok(s) => {
                // What is accepted is sound enough for merge to size by.
                assert!(
                    s.shard < s.of && s.of <= s.search.options.plan,
                    "case {case}"
                );
                assert!(s.seconds.is_finite() && s.seconds >= 0.0, "case {case}");
                accepted += 1;
            }
            Err(f) => {
                // Every refusal is a ShardError: bad input, by its type.
                let msg = f.to_string();
                assert!(msg.starts_with("fuzz/shard-7.json: "), "case {case}: {msg}");
                let names_field = msg.contains('`');
                let names_place = msg.contains(" line ") && msg.contains(" column ");
                assert!(names_field || names_place, "case {case}: {msg}\n{text}");
                refused += 1;
            }
        }
    }
    eprintln!("shard fuzz: {refused} refused, {accepted} accepted of 10000");
    // The loop reaches both outcomes.
    assert!(
        refused > 1000 && accepted > 100,
        "{refused} refused, {accepted} accepted"
    );
}
