//! Unit tests of the free directions.
use super::gram::spring_gram;
use super::vectors::unit_residual;
use super::*;
use crate::io::model_file::parse_model;
use crate::simulation::steps::integrator;
use crate::simulation::Simulator;
use std::path::Path;

/// One body (50 kg, com (0, 0, 0.2)) on one element at `at` to ground
/// with `components`, plus `extra` TOML at the end.
fn model_text(at: &str, components: &str, extra: &str) -> String {
    format!(
        "[simulation]\nduration = 0.01\nsample_rate = 1000.0\n\n\
         [[body]]\nname = \"carriage\"\nmass = 50.0\ninertia = [1.0, 1.5, 2.0]\n\
         com = [0.0, 0.0, 0.2]\n\n\
         [[element]]\nname = \"slideway\"\nbody = \"carriage\"\nto = \"ground\"\n\
         at = {at}\n{components}\n{extra}\n\
         [[sensor]]\nname = \"x\"\nbody = \"carriage\"\nat = [0, 0, 0.2]\n\
         direction = [1, 0, 0]\nquantity = \"displacement\"\n"
    )
}

/// The model of [`model_text`].
fn model(at: &str, components: &str, extra: &str) -> Model {
    let text = model_text(at, components, extra);
    parse_model(&text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// The free set of `m` at its nominal values, described.
fn free_of(m: &Model) -> (FreeSet, Vec<String>) {
    let sim = Simulator::with_integrator(m, integrator(1));
    let sys = sim.system(&m.nominal()).unwrap();
    let free = free_directions(&sys);
    let text = free.descriptions(m);
    (free, text)
}

#[test]
fn a_rotation_free_about_the_elements_point_is_named_with_that_axis() {
    let m = model(
        "[0.05, 0.0, 0.1]",
        "ux = { k = 1e8 }\nuy = { k = 1e8 }\nuz = { k = 2e8 }\n\
         rx = { k = 1e6 }\nry = { k = 1e6 }\nrz = { c = 5.0 }",
        "",
    );
    let (free, text) = free_of(&m);
    assert_eq!(free.len(), 1, "{text:?}");
    assert_eq!(
        text[0],
        "carriage: free to rotate about z through (0.05, 0, 0.2)"
    );
}

/// A body's full six springs at its centre of mass, as a component list.
const FULL: &str = "ux = { k = 1e8 }\nuy = { k = 1e8 }\nuz = { k = 1e8 }\n\
                    rx = { k = 1e6 }\nry = { k = 1e6 }\nrz = { k = 1e6 }";

#[test]
fn a_damper_only_axis_is_free_and_a_skewed_one_is_named_by_its_direction() {
    let (free, text) = free_of(&model(
        "[0, 0, 0.1]",
        &FULL.replace("ux = { k = 1e8 }", "ux = { c = 200.0 }"),
        "",
    ));
    assert_eq!(text, ["carriage: free along x"]);
    assert_eq!(
        free.directions[0].motions,
        [(
            0,
            Motion::Translation {
                direction: Vector3::x()
            }
        )]
    );
    let skew = "axes = [[0.6, 0.8, 0], [-0.8, 0.6, 0], [0, 0, 1]]\n";
    let (_, text) = free_of(&model(
        "[0, 0, 0.1]",
        &format!("{skew}{}", FULL.replace("uy = { k = 1e8 }\n", "")),
        "",
    ));
    // The free direction is e2 = (−0.8, 0.6, 0), its largest component made positive.
    assert_eq!(text, ["carriage: free along (0.8, -0.6, 0)"]);
    // Fully restrained: nothing free.
    assert!(free_of(&model("[0, 0, 0.1]", FULL, "")).0.is_empty());
}

#[test]
fn bodies_joined_by_springs_move_together_and_a_loose_body_has_six_directions() {
    let slide = "[[body]]\nname = \"slide\"\nmass = 20.0\ninertia = [0.3, 0.3, 0.3]\n\
                 com = [0.0, 0.0, 0.4]\n\n[[element]]\nname = \"cross\"\nbody = \"slide\"\n\
                 to = \"carriage\"\nat = [0.0, 0.0, 0.3]\n";
    let rest = FULL.replace("ux = { k = 1e8 }\n", "");
    let (_, text) = free_of(&model("[0, 0, 0.1]", &rest, &format!("{slide}{FULL}\n")));
    assert_eq!(text, ["carriage and slide together: free along x"]);
    let loose = "[[body]]\nname = \"loose\"\nmass = 2.0\ninertia = [0.3, 0.3, 0.3]\n\
                 com = [1.0, 0.0, 0.4]\n";
    let m = model("[0, 0, 0.1]", FULL, loose);
    let (free, text) = free_of(&m);
    assert_eq!(free.len(), 6, "{text:?}");
    assert_eq!(text[2], "loose: free along z");
    assert_eq!(text[5], "loose: free to rotate about z through (1, 0, 0.4)");
}

#[test]
fn gravity_along_a_free_direction_is_named_with_its_pull() {
    let text = model_text(
        "[0, 0, 0.1]",
        &FULL.replace("ux = { k = 1e8 }", "ux = { c = 200.0 }"),
        "",
    );
    let text = format!("gravity = [-1.0, 0.0, -9.76]\n{text}");
    let m = parse_model(&text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"));
    let sim = Simulator::with_integrator(&m, integrator(1));
    let sys = sim.system(&m.nominal()).unwrap();
    let free = free_directions(&sys);
    let pull = free.gravity_load(&sys).expect("pulled");
    assert!((pull.load + 50.0).abs() < 1e-9, "{pull:?}");
    let e = free.check_gravity(&sys).unwrap_err();
    assert!(
        matches!(&e, SimulationError::FreeUnderGravity { body, moment: false, .. } if body == "carriage"),
        "{e:?}"
    );
    let text = e.to_string();
    assert!(
        text.contains("carriage is free along x") && text.contains("50.00 N"),
        "{text}"
    );
}

#[test]
fn the_free_space_is_the_null_space_of_the_spring_rows() {
    // Against the symmetric eigenproblem of G: as many eigenvalues below
    // the tolerance as free directions, and G x = 0 on each.
    let loose = "[[body]]\nname = \"loose\"\nmass = 2.0\ninertia = [0.3, 0.3, 0.3]\n\
                 com = [1.0, 0.0, 0.4]\n";
    let spindle = FULL.replace("rz = { k = 1e6 }", "rz = { c = 5.0 }");
    for m in [
        model("[0.05, 0, 0.1]", &spindle, loose),
        model("[0.05, 0, 0.1]", FULL, ""),
    ] {
        let sim = Simulator::with_integrator(&m, integrator(1));
        let sys = sim.system(&m.nominal()).unwrap();
        let free = free_directions(&sys);
        let n = sys.n;
        let sqrt_m: Vec<f64> = sys.minv.iter().map(|v| 1.0 / v.sqrt()).collect();
        let g = spring_gram(&sys, &sqrt_m);
        let eig = nalgebra::SymmetricEigen::new(nalgebra::DMatrix::from_row_slice(n, n, &g));
        let zero = eig.eigenvalues.iter().filter(|l| l.abs() < 1e-9).count();
        assert_eq!(zero, free.len());
        for x in free.orthonormal() {
            let gx = nalgebra::DMatrix::from_row_slice(n, n, &g)
                * nalgebra::DVector::from_column_slice(x);
            assert!(gx.amax() < 1e-12, "{}", gx.amax());
        }
        // Each described shape lies in the space.
        for d in &free.directions {
            let x: Vec<f64> = d.shape.iter().zip(&sqrt_m).map(|(v, s)| v * s).collect();
            assert!(unit_residual(free.orthonormal(), &x).is_none());
        }
    }
}

/// A body restrained and driven along x alone at its centre of mass is free
/// along its five other coordinates, and nothing can move it along them:
/// inert. A damper across one of them, a load along one, or gravity along
/// one is not.
#[test]
fn free_directions_nothing_acts_along_are_inert() {
    let drive = "[[excitation]]\nname = \"f\"\nbody = \"carriage\"\nat = [0, 0, 0.2]\n\
                 direction = DIR\nsignal = { type = \"sine\", amplitude = 1.0, frequency = 10.0 }\n";
    let inert = |at: &str, components: &str, dir: &str, gravity: bool| {
        let text = model_text(at, components, &drive.replace("DIR", dir));
        let text = match gravity {
            true => format!("gravity = [0.0, 0.0, -9.81]\n{text}"),
            false => text,
        };
        let m = parse_model(&text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"));
        let sim = Simulator::with_integrator(&m, integrator(1));
        let sys = sim.system(&m.nominal()).unwrap();
        let free = free_directions(&sys);
        assert_eq!(free.len(), 5, "{:?}", free.descriptions(&m));
        free.inert(&sys)
    };
    let centre = "[0.0, 0.0, 0.2]";
    assert!(inert(
        centre,
        "ux = { k = 1e6, c = 10.0 }",
        "[1, 0, 0]",
        false
    ));
    // A damper about z: it vanishes at rest, so z stays free, but it acts.
    let damped = "ux = { k = 1e6, c = 10.0 }\nrz = { c = 5.0 }";
    assert!(!inert(centre, damped, "[1, 0, 0]", false));
    // A load with a part along y.
    assert!(!inert(centre, "ux = { k = 1e6 }", "[1, 1, 0]", false));
    // The weight along the free z.
    assert!(!inert(centre, "ux = { k = 1e6 }", "[1, 0, 0]", true));
    // The spring off the centre of mass couples x to a rotation.
    assert!(!inert(
        "[0.0, 0.3, 0.2]",
        "ux = { k = 1e6 }",
        "[1, 0, 0]",
        false
    ));
}

#[test]
fn a_slide_along_a_skewed_element_axis_is_named_relative_to_the_other_body() {
    // The carriage turns about z; the slide is held to it except along
    // e1 = (0.6, 0.8, 0) of their element.
    let slide = "[[body]]\nname = \"slide\"\nmass = 20.0\ninertia = [0.3, 0.3, 0.3]\n\
                 com = [0.0, 0.0, 0.4]\n\n[[element]]\nname = \"cross\"\nbody = \"slide\"\n\
                 to = \"carriage\"\nat = [0.0, 0.0, 0.3]\n\
                 axes = [[0.6, 0.8, 0], [-0.8, 0.6, 0], [0, 0, 1]]\n";
    let turning = FULL.replace("\nrz = { k = 1e6 }", "");
    let held = FULL.replace("ux = { k = 1e8 }\n", "");
    let m = model("[0, 0, 0.1]", &turning, &format!("{slide}{held}\n"));
    let (free, text) = free_of(&m);
    assert_eq!(free.len(), 2, "{text:?}");
    assert_eq!(
        text,
        [
            "slide: free along (0.6, 0.8, 0) relative to carriage",
            "carriage and slide together: free to rotate about z through (0, 0, 0.2)",
        ]
    );
    assert_eq!(
        free.directions[0].sentence(&m),
        "slide is free along (0.6, 0.8, 0) relative to carriage"
    );
}
