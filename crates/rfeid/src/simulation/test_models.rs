//! Small models shared by the simulation module's unit tests.
use crate::io::model_file::parse_model;
use crate::model::Model;
use std::path::Path;

/// A single-degree-of-freedom oscillator of natural frequency `f` Hz
/// (unit mass, k = (2πf)², c = 1), driven by a unit sine of `drive` Hz,
/// sampled at `rate` Hz for 0.05 s; its one sensor reads the displacement.
pub(crate) fn oscillator(f: f64, drive: f64, rate: f64) -> Model {
    damped_oscillator(f, 1.0, drive, rate)
}

/// [`oscillator`] with the damper `c` N·s/m (on its 1 kg) in place of 1.
pub(crate) fn damped_oscillator(f: f64, c: f64, drive: f64, rate: f64) -> Model {
    let k = (2.0 * std::f64::consts::PI * f).powi(2);
    let text = format!(
        "[simulation]\nduration = 0.05\nsample_rate = {rate}\n\n\
         [[body]]\nname = \"b\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\ncom = [0, 0, 0]\n\n\
         [[element]]\nname = \"s\"\nbody = \"b\"\nto = \"ground\"\nat = [0, 0, 0]\n\
         ux = {{ k = {k}, c = {c:e} }}\n\n\
         [[excitation]]\nname = \"p\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
         signal = {{ type = \"sine\", amplitude = 1.0, frequency = {drive} }}\n\n\
         [[sensor]]\nname = \"x\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
         quantity = \"displacement\"\n"
    );
    parse_model(&text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// The oscillator of [`oscillator`] with damping `c` (N·s/m), driven by a
/// unit chirp from `f0` to `f1` Hz over `duration` s, sampled at `rate` Hz.
pub(crate) fn chirped_oscillator(
    f: f64,
    c: f64,
    (f0, f1): (f64, f64),
    rate: f64,
    duration: f64,
) -> Model {
    let k = (2.0 * std::f64::consts::PI * f).powi(2);
    let text = format!(
        "[simulation]\nduration = {duration}\nsample_rate = {rate}\n\n\
         [[body]]\nname = \"b\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\ncom = [0, 0, 0]\n\n\
         [[element]]\nname = \"s\"\nbody = \"b\"\nto = \"ground\"\nat = [0, 0, 0]\n\
         ux = {{ k = {k}, c = {c} }}\n\n\
         [[excitation]]\nname = \"p\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
         signal = {{ type = \"chirp\", amplitude = 1.0, f0 = {f0}, f1 = {f1} }}\n\n\
         [[sensor]]\nname = \"x\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
         quantity = \"displacement\"\n"
    );
    parse_model(&text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
}
