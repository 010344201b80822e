//! Writes a generated machine-tool model (issues 12 and 46) as TOML:
//! `cargo run --release --example machine_tool -- BODIES PARAMS [SHAPE
//! [STIFFER [SEED]]] > model.toml`, SHAPE one of `bed-column` (the default),
//! `chain`, `tower`, `gantry`; STIFFER a factor on the member joints'
//! stiffnesses (default 1); SEED a seed of the geometry's variation (default
//! 0: the nominal geometry). The model is described in
//! `tests/machine_tool/mod.rs`.
#[path = "../tests/machine_tool/mod.rs"]
mod machine_tool;
use machine_tool::{Machine, Shape};

const USAGE: &str = "usage: machine_tool BODIES PARAMS [SHAPE [STIFFER [SEED]]] \
                     (SHAPE: bed-column, chain, tower or gantry; STIFFER > 0)";

fn usage(why: &str) -> ! {
    eprintln!("{why}\n{USAGE}");
    std::process::exit(2)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize| args.get(i).map(String::as_str);
    let whole = |i: usize, default: u64| -> u64 {
        arg(i).map_or(default, |a| {
            a.parse()
                .unwrap_or_else(|_| usage(&format!("'{a}' is not a whole number")))
        })
    };
    let shape = match arg(2) {
        None => Shape::BedColumn,
        Some(name) => *Shape::ALL
            .iter()
            .find(|s| s.name() == name)
            .unwrap_or_else(|| usage(&format!("unknown shape '{name}'"))),
    };
    let stiffer = arg(3).map_or(1.0, |a| match a.parse::<f64>() {
        Ok(f) if f > 0.0 && f.is_finite() => f,
        _ => usage(&format!("STIFFER '{a}' is not a positive number")),
    });
    let machine = Machine {
        shape,
        bodies: whole(0, 10) as usize,
        params: whole(1, 16) as usize,
        stiffer,
        seed: whole(4, 0),
    };
    if machine.bodies < shape.min_bodies() {
        usage(&format!(
            "a {} model has at least {} bodies",
            shape.name(),
            shape.min_bodies()
        ));
    }
    print!("{}", machine_tool::machine_toml(&machine));
}
