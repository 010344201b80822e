//! Reading a model file gives exactly the model it describes: the
//! knee–column example against SPEC §4 (units converted, shared parameters,
//! element axes, the exciter), and the defaults of SPEC §1 and §3.
//!
//! Unit conversion multiplies by powers of ten that are not exact in binary,
//! so converted values are compared to 4 ulps (relative 1e-15); geometry
//! that is written exactly is compared exactly.
use crate::common;

use common::*;
use nalgebra::{Matrix3, Vector3};
use rfeid::io::model_file::load_model;
use rfeid::model::{Attachment, Law, Linear, Model, Power, SensorKind, Shape, Value};
use std::path::Path;

fn knee_column() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    load_model(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-15 * b.abs()
}

fn param(model: &Model, name: &str) -> Value {
    Value::Param(model.parameter_index(name).unwrap())
}

#[test]
fn knee_column_parameters_are_the_papers_in_si() {
    let m = knee_column();
    // (name, min, max, true) in the paper's units, and the unit's SI scale.
    let a_n = 1e13; // daN/µm² = 10 N / 1e-12 m²
    let a_t = 1e7; // daN/µm
    let h = 1e4; // daN·ms/µm
    let table: [(&str, f64, f64, f64, f64); 16] = [
        ("a_n1", 190.0, 570.0, 380.0, a_n),
        ("a_n2", 185.0, 555.0, 370.0, a_n),
        ("a_n3", 170.0, 510.0, 340.0, a_n),
        ("a_n4", 330.0, 990.0, 660.0, a_n),
        ("a_t1", 7.5, 22.5, 15.0, a_t),
        ("a_t2", 7.5, 22.5, 15.0, a_t),
        ("a_t3", 6.5, 19.5, 13.0, a_t),
        ("a_t4", 13.5, 40.5, 27.0, a_t),
        ("h_n1", 1.8, 5.4, 3.6, h),
        ("h_n2", 1.75, 5.25, 3.5, h),
        ("h_n3", 1.35, 4.95, 2.7, h),
        ("h_n4", 1.05, 3.15, 2.1, h),
        ("h_t1", 2.75, 8.25, 5.5, h),
        ("h_t2", 2.75, 8.25, 5.5, h),
        ("h_t3", 0.105, 0.315, 0.21, h),
        ("h_t4", 3.85, 11.55, 7.7, h),
    ];
    assert_eq!(m.parameters.len(), 16);
    assert_eq!(m.identified(), (0..16).collect::<Vec<_>>());
    for (i, (name, lo, hi, value, scale)) in table.iter().enumerate() {
        let p = &m.parameters[i];
        assert_eq!(p.name, *name);
        let (l, u) = p.bounds.unwrap();
        assert!(
            close(p.value, value * scale),
            "{name}: {} vs {}",
            p.value,
            value * scale
        );
        assert!(close(l, lo * scale) && close(u, hi * scale), "{name}: box");
        assert!(
            close(p.unit.scale, *scale),
            "{name}: display unit {:?}",
            p.unit
        );
    }
    assert_eq!(m.parameters[0].unit.symbol, "daN/um^2");
    assert_eq!(m.nominal()[4], m.parameters[4].value);
}

#[test]
fn knee_column_geometry_and_experiment_are_spec_section_4() {
    let m = knee_column();
    let (column, knee) = (&m.bodies[0], &m.bodies[1]);
    assert_eq!(
        (column.name.as_str(), knee.name.as_str()),
        ("column", "knee")
    );
    assert_eq!(column.mass, Value::Fixed(900.0));
    assert_eq!(column.inertia, [219.0, 210.75, 45.75].map(Value::Fixed));
    assert_eq!(column.com, Vector3::new(0.0, 0.0, 0.8));
    assert_eq!(knee.mass, Value::Fixed(320.0));
    assert_eq!(knee.inertia, [18.47, 10.8, 18.47].map(Value::Fixed));
    assert_eq!(knee.com, Vector3::new(0.0, 0.65, 0.75));
    assert_eq!(knee.axes, Matrix3::identity());

    assert_eq!(m.elements.len(), 9);
    let s1 = &m.elements[0];
    assert_eq!((s1.body, s1.to), (1, Attachment::Body(0)));
    assert_eq!(s1.at, Vector3::new(-0.2, 0.3, 0.95));
    // Columns e1 = Y (normal), e2 = Z, e3 = X.
    let e = Matrix3::from_columns(&[Vector3::y(), Vector3::z(), Vector3::x()]);
    assert!((s1.axes - e).amax() < 1e-15);
    let dofs: Vec<usize> = s1.components.iter().map(|c| c.dof).collect();
    assert_eq!(dofs, [0, 1, 2]);
    assert_eq!(
        s1.components[0].law,
        Law::Power(Power {
            a: param(&m, "a_n1"),
            m: Value::Fixed(2.0),
            reference: 1.0
        })
    );
    assert_eq!(s1.components[0].damping, param(&m, "h_n1"));
    // uy and uz share a_t1 and h_t1.
    for c in &s1.components[1..] {
        assert_eq!(
            c.law,
            Law::Linear(Linear {
                k: param(&m, "a_t1")
            })
        );
        assert_eq!(c.damping, param(&m, "h_t1"));
    }
    // Slideway 3's normal is (1, 1, 0)/√2, its axes orthonormal to rounding.
    let s3 = &m.elements[2];
    let r = std::f64::consts::FRAC_1_SQRT_2;
    assert!((s3.axes.column(0) - Vector3::new(r, r, 0.0)).amax() < 1e-15);
    assert!((s3.axes.transpose() * s3.axes - Matrix3::identity()).amax() < 1e-15);
    // The screw: uz only, fixed values with units.
    let screw = &m.elements[4];
    assert_eq!(screw.components.len(), 1);
    assert_eq!(screw.components[0].dof, 2);
    let Law::Linear(Linear { k: Value::Fixed(k) }) = screw.components[0].law else {
        panic!("screw law {:?}", screw.components[0].law)
    };
    assert!(close(k, 2.0e8));
    assert_eq!(screw.axes, Matrix3::identity());
    // Pads to ground.
    for pad in &m.elements[5..] {
        assert_eq!((pad.body, pad.to), (0, Attachment::Ground));
        assert_eq!(pad.components.len(), 3);
    }

    let x = &m.excitations[0];
    assert_eq!((x.body, x.reaction), (1, Some(0)));
    let d = Vector3::new(1.0, 2.0, 1.0) / 6f64.sqrt();
    assert!((x.direction - d).amax() < 1e-16);
    assert_eq!(x.signal.terms.len(), 1);
    let Value::Fixed(amp) = x.signal.terms[0].amplitude else {
        panic!()
    };
    assert!(close(amp, 1000.0));
    assert_eq!(
        x.signal.terms[0].shape,
        Shape::Sine {
            frequency: 80.0,
            phase: 0.0
        }
    );

    let names: Vec<&str> = m.sensors.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["knee_ax", "knee_ay", "knee_az"]);
    for (s, n) in m
        .sensors
        .iter()
        .zip([Vector3::x(), Vector3::y(), Vector3::z()])
    {
        assert_eq!(
            (s.body, s.kind, s.at, s.direction),
            (1, SensorKind::Acceleration, knee.com, n)
        );
    }
    assert_eq!(m.sampling.n_samples(), 3000);
    assert!(close(m.sampling.duration, 0.3) && close(m.sampling.sample_rate, 1e4));
    assert_eq!(m.gravity, None);
}

/// Defaults: global axes, no damping, automatic steps, an excitation named by
/// its number, a chirp that sweeps the whole record.
#[test]
fn defaults_are_those_of_the_spec() {
    let m = model(
        r#"
[simulation]
duration = "250 ms"
sample_rate = "2 kHz"

[[body]]
name = "b"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "s"
body = "b"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { k = 1e6 }
rz = { c = "3 N*m*s/rad" }

[[excitation]]
body = "b"
at = [0.0, 0.0, 0.0]
direction = [0, 0, 2]
signal = { type = "chirp", amplitude = 1.0, f0 = 10.0, f1 = 100.0 }

[[sensor]]
name = "x"
body = "b"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "velocity"
"#,
    );
    assert_eq!(m.bodies[0].axes, Matrix3::identity());
    assert_eq!(m.elements[0].axes, Matrix3::identity());
    assert_eq!(m.elements[0].components[0].damping, Value::Fixed(0.0));
    assert_eq!(m.elements[0].components[1].law, Law::None);
    assert_eq!(m.elements[0].components[1].dof, 5);
    assert_eq!(m.elements[0].components[1].damping, Value::Fixed(3.0));
    assert_eq!(m.sampling.substeps, None);
    assert_eq!(m.sampling.tolerance, rfeid::simulation::DEFAULT_TOLERANCE);
    assert_eq!(m.sampling.n_samples(), 500);
    assert_eq!(m.excitations[0].name, "excitation 1");
    assert_eq!(m.excitations[0].direction, Vector3::z());
    assert_eq!(
        m.excitations[0].signal.terms[0].shape,
        Shape::Chirp {
            f0: 10.0,
            f1: 100.0,
            duration: 0.25
        }
    );
    assert!(m.parameters.is_empty());
}
