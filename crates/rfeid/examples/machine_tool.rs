//! Writes a generated machine-tool model (issue 12) as TOML:
//! `cargo run --release --example machine_tool -- BODIES PARAMS > model.toml`.
//! The model is described in `tests/machine_tool/mod.rs`.
#[path = "../tests/machine_tool/mod.rs"]
mod machine_tool;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parse = |i: usize, default: usize| -> usize {
        args.get(i).map_or(default, |a| {
            a.parse().unwrap_or_else(|_| {
                eprintln!("usage: machine_tool BODIES PARAMS (whole numbers; BODIES >= 2)");
                std::process::exit(2)
            })
        })
    };
    let (bodies, params) = (parse(0, 10), parse(1, 16));
    if bodies < 2 {
        eprintln!("usage: machine_tool BODIES PARAMS (BODIES >= 2)");
        std::process::exit(2);
    }
    print!("{}", machine_tool::machine_tool_toml(bodies, params));
}
