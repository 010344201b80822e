//! Machine-tool-like models of any size (issue 12): flexible members as
//! chains of rigid elements joined by stiff 6-component joints (the rigid
//! finite element method), slideways with power-law normals (eq. 6: m = 1.5
//! under the table, m = 2 under the ram) preloaded by gravity, isolation
//! pads, a shaker between tool and workpiece (a 20 N chirp, 20–800 Hz, small
//! enough that the bed and column's contacts stay closed; on the chain and
//! the tower a slideway contact passes through δ = 0 at a resonance, see
//! docs/benchmarks.md), and 3–6 accelerometers; 0.3 s at 10 kHz, steps
//! chosen for the default tolerance.
//!
//! [`machine_tool_toml`] writes the original layout (a bed and a column);
//! [`machine_toml`] writes any [`Machine`]: four [`Shape`]s (issue 46), the
//! member joints made stiffer by a factor, and the geometry varied by a seed.
//!
//! Shared by the tests (`mod machine_tool;`), the benches and the example
//! `machine_tool` (through `#[path]`), which writes the TOML.
#![allow(dead_code)]
use std::fmt::Write;

/// Length of one rigid element of a flexible member, m (before the seed's
/// variation).
const ELEMENT: f64 = 0.5;

/// How a generated machine's members are arranged.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A bed and a column on its last element, about half the members
    /// each; a table on the bed and a ram on the column (the original).
    BedColumn,
    /// A long bed alone, the table on its first element and the ram (a
    /// tailstock) on its last: one chain of joints.
    Chain,
    /// A short bed (a sixth of the members) under a tall column.
    Tower,
    /// Two columns on the bed's ends, joined at the top by a cross-beam that
    /// carries the ram: a closed loop of joints.
    Gantry,
}

impl Shape {
    /// Every shape, in order.
    pub const ALL: [Shape; 4] = [Shape::BedColumn, Shape::Chain, Shape::Tower, Shape::Gantry];

    /// The shape's name as the example `machine_tool` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Shape::BedColumn => "bed-column",
            Shape::Chain => "chain",
            Shape::Tower => "tower",
            Shape::Gantry => "gantry",
        }
    }

    /// The smallest number of bodies the shape is built with.
    pub fn min_bodies(self) -> usize {
        match self {
            Shape::BedColumn | Shape::Chain | Shape::Tower => 2,
            Shape::Gantry => 7,
        }
    }
}

/// A generated machine.
#[derive(Debug, Clone, Copy)]
pub struct Machine {
    /// The arrangement of the members.
    pub shape: Shape,
    /// Number of bodies (at least [`Shape::min_bodies`]).
    pub bodies: usize,
    /// At most this many identified parameters.
    pub params: usize,
    /// Factor on the member joints' stiffnesses (1: the defaults).
    pub stiffer: f64,
    /// Seed of the geometry's variation (0: none, the nominal geometry).
    pub seed: u64,
}

/// A factor in `[lo, hi]` drawn from `state` (SplitMix64), or 1 for the
/// nominal geometry (`state` = 0 stays 0).
fn vary(state: &mut u64, lo: f64, hi: f64) -> f64 {
    if *state == 0 {
        return 1.0;
    }
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
}

/// The layout of a B-body model: a bed of `bed` elements along x on
/// pads, a column of `column` elements along z standing on the bed's last
/// element, a table on slideways on the bed element `table_on` and, with a
/// ram, a ram on slideways on the top element of the column (or the bed's
/// last element without a column, or the cross-beam's middle element of a
/// gantry, whose second column of `column2` elements stands on the bed's
/// first element and whose `beam` elements join the two tops).
#[derive(Debug, Clone, Copy)]
struct Layout {
    bed: usize,
    column: usize,
    column2: usize,
    beam: usize,
    ram: bool,
    table_on: usize,
    /// Length of one element, m.
    element: f64,
    /// Factors on the masses and inertias of the members and of the slides.
    member_mass: f64,
    slide_mass: f64,
    /// Factor on the pads' stiffnesses.
    pads: f64,
    /// Factors on the half-spans of the table's and the ram's slideways.
    spans: [f64; 2],
    /// Factor on the member joints' stiffnesses.
    stiffer: f64,
}

impl Layout {
    fn of(m: &Machine) -> Layout {
        let bodies = m.bodies;
        assert!(
            bodies >= m.shape.min_bodies(),
            "a {} model has at least {} bodies",
            m.shape.name(),
            m.shape.min_bodies()
        );
        let ram = match m.shape {
            Shape::BedColumn => bodies >= 4,
            Shape::Chain | Shape::Tower => bodies >= 3,
            Shape::Gantry => true,
        };
        let members = bodies - 1 - usize::from(ram);
        let (mut bed, mut column, mut column2, mut beam) = (members.div_ceil(2), 0, 0, 0);
        match m.shape {
            Shape::BedColumn => column = members - bed,
            Shape::Chain => bed = members,
            Shape::Tower => {
                bed = (members / 6).max(1);
                column = members - bed;
            }
            Shape::Gantry => {
                beam = (members / 6).max(1);
                bed = (members / 3).max(2);
                column = (members - bed - beam) / 2;
                column2 = column;
                bed = members - beam - 2 * column;
            }
        }
        let mut state = m.seed.wrapping_mul(0x2545_F491_4F6C_DD1D);
        let element = ELEMENT * vary(&mut state, 0.8, 1.25);
        let member_mass = vary(&mut state, 0.8, 1.25);
        let slide_mass = vary(&mut state, 0.7, 1.4);
        let pads = vary(&mut state, 0.6, 1.6);
        let spans = [vary(&mut state, 0.75, 1.3), vary(&mut state, 0.75, 1.3)];
        // The table on the bed's first element, a gantry's on its middle
        // (its first carries the second column); a seed moves it along the
        // first half.
        let table_on = match (m.seed, m.shape) {
            (0, Shape::Gantry) => bed / 2,
            (0, _) => 0,
            (_, shape) => {
                let first = usize::from(shape == Shape::Gantry);
                (((vary(&mut state, 0.0, 1.0) * bed as f64) as usize).min(bed - 1) / 2).max(first)
            }
        };
        Layout {
            bed,
            column,
            column2,
            beam,
            ram,
            table_on,
            element,
            member_mass,
            slide_mass,
            pads,
            spans,
            stiffer: m.stiffer,
        }
    }

    /// Global x of the centre of bed element i.
    fn bed_x(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * self.element - self.bed as f64 * self.element / 2.0
    }

    /// The length of a cross-beam element, m.
    fn beam_element(&self) -> f64 {
        (self.bed_x(self.bed - 1) - self.bed_x(0)) / self.beam as f64
    }

    /// Global x of the centre of cross-beam element i.
    fn beam_x(&self, i: usize) -> f64 {
        self.bed_x(0) + (i as f64 + 0.5) * self.beam_element()
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
        0.6 + self.column as f64 * self.element
    }

    /// Height of the ram's slideway: the column's top, or a gantry's
    /// cross-beam's upper face.
    fn ram_base(&self) -> f64 {
        match self.beam {
            0 => self.column_top(),
            _ => self.column_top() + 0.5,
        }
    }

    /// Global x of the ram's slideway: over the column, or at the middle of
    /// a gantry's cross-beam.
    fn ram_x(&self) -> f64 {
        match self.beam {
            0 => self.bed_x(self.bed - 1),
            _ => self.beam_x(self.beam / 2),
        }
    }

    /// The number of 6-component joints in the members.
    fn joints(&self) -> usize {
        let closing = usize::from(self.beam > 0);
        self.bed.saturating_sub(1) + self.column + self.column2 + self.beam + closing
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
        s.push((format!("pad{p}_k_xy"), 2.0e8 * layout.pads));
        s.push((format!("pad{p}_k_z"), 4.0e8 * layout.pads));
        s.push((format!("pad{p}_c"), 2.0e4));
    }
    for j in 1..=layout.joints() {
        s.push((format!("joint{j}_k_t"), 3.0e9 * layout.stiffer));
        s.push((format!("joint{j}_k_r"), 3.0e8 * layout.stiffer));
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
    machine_toml(&Machine {
        shape: Shape::BedColumn,
        bodies,
        params,
        stiffer: 1.0,
        seed: 0,
    })
}

/// The model file of the machine `m` (see [`Machine`]); for the original
/// shape without variation, [`machine_tool_toml`]'s.
pub fn machine_toml(m: &Machine) -> String {
    let layout = Layout::of(m);
    let mut head = header(layout, m.bodies);
    if m.shape != Shape::BedColumn || m.stiffer != 1.0 || m.seed != 0 {
        head = format!(
            "# Shape {}, {} beam element(s), member joints {}× the default stiffness, \
             geometry seed {}.\n{head}",
            m.shape.name(),
            layout.beam,
            m.stiffer,
            m.seed
        );
    }
    toml(layout, m.params, head)
}

/// The first line of a model file: what it holds.
fn header(layout: Layout, bodies: usize) -> String {
    format!(
        "# A generated machine-tool model: {bodies} bodies ({} bed and {} column \
         elements, a table{})",
        layout.bed,
        layout.column + layout.column2,
        if layout.ram { " and a ram" } else { "" },
    )
}

/// The model file of `layout` with up to `params` identified parameters
/// under the first line `head`.
fn toml(layout: Layout, params: usize, head: String) -> String {
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
        "{head}, {} identified parameters.\n\
         gravity = [0.0, 0.0, -9.81]\n\n[simulation]\nduration = \"0.3 s\"\n\
         sample_rate = \"10 kHz\"\n",
        identified.len()
    )
    .unwrap();
    // A body of mass and inertia scaled by `f` (the seed's variation).
    let body =
        |w: &mut String, name: &str, f: f64, (mass, inertia): (f64, [f64; 3]), com: [f64; 3]| {
            let (mass, inertia) = (mass * f, inertia.map(|j| j * f));
            writeln!(
                w,
                "[[body]]\nname = \"{name}\"\nmass = {mass:e}\ninertia = {inertia:?}\n\
             com = {com:?}\n"
            )
            .unwrap();
        };
    let (fm, fs) = (layout.member_mass, layout.slide_mass);
    for i in 0..layout.bed {
        let at = [layout.bed_x(i), 0.0, 0.3];
        body(w, &format!("bed{i}"), fm, (400.0, [17.0, 14.0, 20.0]), at);
    }
    let column_x = layout.bed_x(layout.bed - 1);
    let columns = [
        ("column", layout.column, column_x),
        ("column2_", layout.column2, layout.bed_x(0)),
    ];
    for (name, n, x) in columns {
        for i in 0..n {
            let z = 0.6 + (i as f64 + 0.5) * layout.element;
            body(
                w,
                &format!("{name}{i}"),
                fm,
                (300.0, [12.0, 11.0, 9.0]),
                [x, 0.0, z],
            );
        }
    }
    for i in 0..layout.beam {
        let z = layout.column_top() + 0.25;
        let at = [layout.beam_x(i), 0.0, z];
        body(w, &format!("beam{i}"), fm, (300.0, [9.0, 12.0, 11.0]), at);
    }
    let table_x = layout.bed_x(layout.table_on);
    body(
        w,
        "table",
        fs,
        (250.0, [8.0, 6.0, 12.0]),
        [table_x, 0.0, 0.75],
    );
    let ram_x = layout.ram_x();
    if layout.ram {
        let z = layout.ram_base() + 0.15;
        body(w, "ram", fs, (200.0, [9.0, 3.0, 9.0]), [ram_x, 0.2, z]);
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
        let at = [layout.bed_x(i) - layout.element / 2.0, 0.0, 0.3];
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
    let feet = [layout.bed - 1, 0];
    for ((name, n, x), foot) in columns.into_iter().zip(feet) {
        for i in 0..n {
            joint += 1;
            let below = match i {
                0 => format!("bed{foot}"),
                _ => format!("{name}{}", i - 1),
            };
            let at = [x, 0.0, 0.6 + i as f64 * layout.element];
            let comps = joint_comps(joint);
            element(
                w,
                &format!("{name}_joint{i}"),
                &format!("{name}{i}"),
                &below,
                at,
                &comps,
            );
        }
    }
    // A gantry's cross-beam: from the second column's top, element by
    // element, to the first column's top (the joint that closes the loop).
    let top_z = layout.column_top();
    let beam_joints = match layout.beam {
        0 => 0..0,
        n => 0..n + 1,
    };
    for i in beam_joints {
        joint += 1;
        let (from, to, x) = match i {
            0 => (
                "beam0".to_string(),
                format!("column2_{}", layout.column2 - 1),
                layout.bed_x(0),
            ),
            i if i == layout.beam => (
                format!("beam{}", i - 1),
                format!("column{}", layout.column - 1),
                column_x,
            ),
            i => (
                format!("beam{i}"),
                format!("beam{}", i - 1),
                layout.bed_x(0) + i as f64 * layout.beam_element(),
            ),
        };
        let comps = joint_comps(joint);
        element(
            w,
            &format!("beam_joint{i}"),
            &from,
            &to,
            [x, 0.0, top_z],
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
    let [table_span, ram_span] = layout.spans;
    let table_bed = format!("bed{}", layout.table_on);
    let half = [0.2 * table_span, 0.25 * table_span];
    slideway(w, "table", &table_bed, 1.5, [table_x, 0.0, 0.6], half);
    let top = match layout.column {
        0 => format!("bed{}", layout.bed - 1),
        n => format!("column{}", n - 1),
    };
    let ram_on = match layout.beam {
        0 => top.clone(),
        n => format!("beam{}", n / 2),
    };
    if layout.ram {
        let z = layout.ram_base();
        let half = [0.15 * ram_span, 0.3 * ram_span];
        slideway(w, "ram", &ram_on, 2.0, [ram_x, 0.2, z], half);
    }

    // The shaker between tool and workpiece.
    let (tool, at) = match layout.ram {
        true => ("ram", [ram_x, 0.3, layout.ram_base() + 0.3]),
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
        let z = layout.ram_base() + 0.2;
        sensor(w, "ram_a1", "ram", [ram_x, 0.4, z], [1.0, -0.5, 0.3]);
        sensor(w, "ram_a2", "ram", [ram_x + 0.1, 0.0, z], [0.3, 1.0, -0.4]);
        let z = layout.column_top() + 0.2;
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
