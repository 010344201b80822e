//! Machine-tool-like models of any size (issue 12): flexible members as
//! chains of rigid elements joined by stiff 6-component joints (the rigid
//! finite element method), slideways with power-law normals (eq. 6: m = 1.5
//! under the table, m = 2 under the ram) preloaded by gravity, isolation
//! pads, a shaker between tool and workpiece (a 20 N chirp, 20–800 Hz, small
//! enough that the contacts stay closed), and 3–6 accelerometers; 0.3 s
//! at 10 kHz, steps chosen for the default tolerance.
//!
//! Shared by the tests (`mod machine_tool;`), the benches and the example
//! `machine_tool` (through `#[path]`), which writes the TOML.
#![allow(dead_code)]
use std::fmt::Write;

/// Length of one rigid element of a flexible member, m.
const ELEMENT: f64 = 0.5;

/// The layout of a B-body model: a bed of `bed` elements along x on four
/// pads, a column of `column` elements along z standing on the bed's last
/// element, a table on slideways on the bed and, with a column, a ram on
/// slideways on the column's top element (B ≥ 4).
#[derive(Debug, Clone, Copy)]
struct Layout {
    bed: usize,
    column: usize,
    ram: bool,
}

impl Layout {
    fn new(bodies: usize) -> Layout {
        assert!(bodies >= 2, "a machine-tool model has at least two bodies");
        let ram = bodies >= 4;
        let members = bodies - 1 - usize::from(ram);
        let bed = members.div_ceil(2);
        Layout {
            bed,
            column: members - bed,
            ram,
        }
    }

    /// Global x of the centre of bed element i.
    fn bed_x(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * ELEMENT - self.bed as f64 * ELEMENT / 2.0
    }

    /// The isolation pads: `(bed element, x offset, y)`. Every fourth bed
    /// element and the last rest on two pads; a one-element bed on four.
    fn pads(&self) -> Vec<(usize, f64, f64)> {
        let mut elements: Vec<usize> = (0..self.bed).step_by(4).collect();
        if elements.last() != Some(&(self.bed - 1)) {
            elements.push(self.bed - 1);
        }
        let xs: &[f64] = if elements.len() == 1 {
            &[-0.2, 0.2]
        } else {
            &[0.0]
        };
        let mut pads = Vec::new();
        for e in elements {
            for &x in xs {
                pads.push((e, x, -0.3));
                pads.push((e, x, 0.3));
            }
        }
        pads
    }

    /// Height of the column's top.
    fn column_top(&self) -> f64 {
        0.6 + self.column as f64 * ELEMENT
    }
}

/// Every place a parameter can stand, in the order in which they become
/// identified: the slideway contacts first, then the pads, then the joints
/// of the flexible members. Each is `(name, nominal value)`.
///
/// The tangential springs and dampers of a slideway's fourth contact are
/// never identified (see [`fixed_sites`]): a rigid slide moves in its plane
/// in three coordinates (x, y, rz), which see only three combinations of
/// four corner stiffnesses (Σk, Σk·x, Σk·y), so the fourth is not
/// identifiable from any data (a scaled Fisher condition number of 10²⁹).
fn sites(layout: Layout) -> Vec<(String, f64)> {
    let mut s = Vec::new();
    for (slide, a_n) in [("table", 1.2e11), ("ram", 4.0e13)] {
        if slide == "ram" && !layout.ram {
            continue;
        }
        for c in 1..=4 {
            s.push((format!("{slide}_a_n{c}"), a_n * (1.0 + 0.1 * c as f64)));
            s.push((format!("{slide}_h_n{c}"), 1.0e4));
        }
        for c in 1..=3 {
            s.push(tangential(slide, c).0);
            s.push(tangential(slide, c).1);
        }
    }
    for p in 1..=layout.pads().len() {
        s.push((format!("pad{p}_k_xy"), 2.0e8));
        s.push((format!("pad{p}_k_z"), 4.0e8));
        s.push((format!("pad{p}_c"), 2.0e4));
    }
    let joints = layout.bed.saturating_sub(1) + layout.column;
    for j in 1..=joints {
        s.push((format!("joint{j}_k_t"), 3.0e9));
        s.push((format!("joint{j}_k_r"), 3.0e8));
    }
    s
}

/// The tangential stiffness and damping sites of contact `c` of `slide`.
fn tangential(slide: &str, c: usize) -> ((String, f64), (String, f64)) {
    (
        (format!("{slide}_a_t{c}"), 1.5e8 * (1.0 + 0.05 * c as f64)),
        (format!("{slide}_h_t{c}"), 4.0e3),
    )
}

/// The sites that are never identified (see [`sites`]).
fn fixed_sites() -> Vec<(String, f64)> {
    ["table", "ram"]
        .iter()
        .flat_map(|slide| {
            let (a, h) = tangential(slide, 4);
            [a, h]
        })
        .collect()
}

/// The model file of a machine tool with `bodies` bodies (≥ 2) and up to
/// `params` identified parameters (fewer if the model has fewer places for
/// them; every box is a factor of 2 each way around the nominal value).
pub fn machine_tool_toml(bodies: usize, params: usize) -> String {
    let layout = Layout::new(bodies);
    let all = sites(layout);
    let identified = &all[..params.min(all.len())];
    let fixed = fixed_sites();
    let nominal = |name: &str| -> f64 {
        all.iter()
            .chain(&fixed)
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("no site {name}"))
            .1
    };
    // A value: the parameter's name if identified, else the number.
    let v = |name: &str| -> String {
        match identified.iter().any(|(n, _)| n == name) {
            true => format!("\"{name}\""),
            false => format!("{:e}", nominal(name)),
        }
    };
    let mut t = String::new();
    let w = &mut t;
    writeln!(
        w,
        "# A generated machine-tool model: {bodies} bodies ({} bed and {} column \
         elements, a table{}), {} identified parameters.\n\
         gravity = [0.0, 0.0, -9.81]\n\n[simulation]\nduration = \"0.3 s\"\n\
         sample_rate = \"10 kHz\"\n",
        layout.bed,
        layout.column,
        if layout.ram { " and a ram" } else { "" },
        identified.len()
    )
    .unwrap();
    let body = |w: &mut String, name: &str, mass: f64, inertia: [f64; 3], com: [f64; 3]| {
        writeln!(
            w,
            "[[body]]\nname = \"{name}\"\nmass = {mass:e}\ninertia = {inertia:?}\n\
             com = {com:?}\n"
        )
        .unwrap();
    };
    for i in 0..layout.bed {
        body(
            w,
            &format!("bed{i}"),
            400.0,
            [17.0, 14.0, 20.0],
            [layout.bed_x(i), 0.0, 0.3],
        );
    }
    let column_x = layout.bed_x(layout.bed - 1);
    for i in 0..layout.column {
        let z = 0.6 + (i as f64 + 0.5) * ELEMENT;
        body(
            w,
            &format!("column{i}"),
            300.0,
            [12.0, 11.0, 9.0],
            [column_x, 0.0, z],
        );
    }
    let table_x = layout.bed_x(0);
    body(w, "table", 250.0, [8.0, 6.0, 12.0], [table_x, 0.0, 0.75]);
    if layout.ram {
        let z = layout.column_top() + 0.15;
        body(w, "ram", 200.0, [9.0, 3.0, 9.0], [column_x, 0.2, z]);
    }

    let element = |w: &mut String, name: &str, from: &str, to: &str, at: [f64; 3], extra: &str| {
        writeln!(
            w,
            "[[element]]\nname = \"{name}\"\nbody = \"{from}\"\nto = \"{to}\"\nat = {at:?}\n{extra}"
        )
        .unwrap();
    };
    for (p, (e, x, y)) in layout.pads().into_iter().enumerate() {
        let (k_xy, k_z, c) = (
            v(&format!("pad{}_k_xy", p + 1)),
            v(&format!("pad{}_k_z", p + 1)),
            v(&format!("pad{}_c", p + 1)),
        );
        let comps = format!(
            "ux = {{ k = {k_xy}, c = {c} }}\nuy = {{ k = {k_xy}, c = {c} }}\n\
             uz = {{ k = {k_z}, c = {c} }}\n"
        );
        let at = [layout.bed_x(e) + x, y, 0.0];
        element(
            w,
            &format!("pad{}", p + 1),
            &format!("bed{e}"),
            "ground",
            at,
            &comps,
        );
    }
    // The joints of the flexible members: six stiff components each.
    let mut joint = 0;
    let joint_comps = |joint: usize| {
        let (k_t, k_r) = (
            v(&format!("joint{joint}_k_t")),
            v(&format!("joint{joint}_k_r")),
        );
        format!(
            "ux = {{ k = {k_t}, c = 2e4 }}\nuy = {{ k = {k_t}, c = 2e4 }}\n\
             uz = {{ k = {k_t}, c = 2e4 }}\nrx = {{ k = {k_r}, c = 500.0 }}\n\
             ry = {{ k = {k_r}, c = 500.0 }}\nrz = {{ k = {k_r}, c = 500.0 }}\n"
        )
    };
    for i in 1..layout.bed {
        joint += 1;
        let at = [layout.bed_x(i) - ELEMENT / 2.0, 0.0, 0.3];
        let comps = joint_comps(joint);
        element(
            w,
            &format!("bed_joint{i}"),
            &format!("bed{i}"),
            &format!("bed{}", i - 1),
            at,
            &comps,
        );
    }
    for i in 0..layout.column {
        joint += 1;
        let below = match i {
            0 => format!("bed{}", layout.bed - 1),
            _ => format!("column{}", i - 1),
        };
        let at = [column_x, 0.0, 0.6 + i as f64 * ELEMENT];
        let comps = joint_comps(joint);
        element(
            w,
            &format!("column_joint{i}"),
            &format!("column{i}"),
            &below,
            at,
            &comps,
        );
    }
    // Slideways: normal along z (e1), preloaded by the slide's weight.
    let slideway =
        |w: &mut String, slide: &str, on: &str, m: f64, centre: [f64; 3], half: [f64; 2]| {
            for (c, (sx, sy)) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
                .iter()
                .enumerate()
            {
                let c = c + 1;
                let [a_n, h_n, a_t, h_t] =
                    ["a_n", "h_n", "a_t", "h_t"].map(|p| v(&format!("{slide}_{p}{c}")));
                let comps = format!(
                    "axes = [[0, 0, 1], [1, 0, 0], [0, 1, 0]]\n\
                 ux = {{ law = \"power\", a = {a_n}, m = {m}, c = {h_n} }}\n\
                 uy = {{ k = {a_t}, c = {h_t} }}\nuz = {{ k = {a_t}, c = {h_t} }}\n"
                );
                let at = [
                    centre[0] + sx * half[0],
                    centre[1] + sy * half[1],
                    centre[2],
                ];
                element(w, &format!("{slide}{c}"), slide, on, at, &comps);
            }
        };
    slideway(w, "table", "bed0", 1.5, [table_x, 0.0, 0.6], [0.2, 0.25]);
    let top = match layout.column {
        0 => format!("bed{}", layout.bed - 1),
        n => format!("column{}", n - 1),
    };
    if layout.ram {
        let z = layout.column_top();
        slideway(w, "ram", &top, 2.0, [column_x, 0.2, z], [0.15, 0.3]);
    }

    // The shaker between tool and workpiece.
    let (tool, at) = match layout.ram {
        true => ("ram", [column_x, 0.3, layout.column_top() + 0.3]),
        false => (top.as_str(), [table_x, 0.05, 0.85]),
    };
    writeln!(
        w,
        "[[excitation]]\nname = \"shaker\"\nbody = \"table\"\nreaction = \"{tool}\"\n\
         at = {at:?}\ndirection = [1.0, 0.5, 0.8]\n\
         signal = {{ type = \"chirp\", amplitude = \"20 N\", f0 = \"20 Hz\", f1 = \"800 Hz\" }}\n"
    )
    .unwrap();
    let sensor = |w: &mut String, name: &str, on: &str, at: [f64; 3], dir: [f64; 3]| {
        writeln!(
            w,
            "[[sensor]]\nname = \"{name}\"\nbody = \"{on}\"\nat = {at:?}\n\
             direction = {dir:?}\nquantity = \"acceleration\"\n"
        )
        .unwrap();
    };
    sensor(
        w,
        "table_a1",
        "table",
        [table_x + 0.1, 0.1, 0.8],
        [1.0, 0.3, 0.5],
    );
    sensor(
        w,
        "table_a2",
        "table",
        [table_x - 0.1, -0.1, 0.8],
        [0.2, 1.0, 0.4],
    );
    let mid = layout.bed / 2;
    sensor(
        w,
        "bed_a",
        &format!("bed{mid}"),
        [layout.bed_x(mid), 0.2, 0.5],
        [0.5, 0.4, 1.0],
    );
    if layout.ram {
        let z = layout.column_top() + 0.2;
        sensor(w, "ram_a1", "ram", [column_x, 0.4, z], [1.0, -0.5, 0.3]);
        sensor(
            w,
            "ram_a2",
            "ram",
            [column_x + 0.1, 0.0, z],
            [0.3, 1.0, -0.4],
        );
        sensor(
            w,
            "column_a",
            &top,
            [column_x + 0.2, 0.0, z - 0.3],
            [0.7, 0.7, 0.2],
        );
    }

    for (name, value) in identified {
        writeln!(
            w,
            "[[parameter]]\nname = \"{name}\"\nvalue = {value:e}\nmin = {:e}\nmax = {:e}\n",
            value / 2.0,
            value * 2.0
        )
        .unwrap();
    }
    t
}
