//! Validated edits of a [`Model`]: a parameter fixed at a value, a nominal
//! value changed, the integrator's steps set. Each edit checks what the
//! model-file reader checks, so the edited model is as trustworthy as one
//! read from a file.
use super::Model;
use crate::simulation::{MAX_SUBSTEPS, TOLERANCE_RANGE};

/// A parameter named or numbered, as an edit addresses it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterRef<'a> {
    /// The parameter with this name.
    Name(&'a str),
    /// The parameter with this index in [`Model::parameters`].
    Index(usize),
}

impl<'a> From<&'a str> for ParameterRef<'a> {
    fn from(name: &'a str) -> Self {
        ParameterRef::Name(name)
    }
}

impl From<usize> for ParameterRef<'_> {
    fn from(index: usize) -> Self {
        ParameterRef::Index(index)
    }
}

/// Why an edit of a model was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError {
    /// No parameter has this name.
    #[error("no parameter is named '{0}'")]
    UnknownName(String),
    /// No parameter has this index.
    #[error("no parameter has the index {index} (the model has {count})")]
    UnknownIndex {
        /// The index asked for.
        index: usize,
        /// How many parameters the model has.
        count: usize,
    },
    /// The value is infinite or not a number.
    #[error("parameter '{name}': {value} is not a finite number")]
    NotFinite {
        /// The parameter's name.
        name: String,
        /// The value refused.
        value: f64,
    },
    /// The value lies outside the parameter's search box.
    #[error("parameter '{name}': {value} lies outside its box [{min:e}, {max:e}]")]
    OutsideBox {
        /// The parameter's name.
        name: String,
        /// The value refused.
        value: f64,
        /// The box's lower end, SI.
        min: f64,
        /// The box's upper end, SI.
        max: f64,
    },
    /// The tolerance lies outside [`TOLERANCE_RANGE`].
    #[error("tolerance {0}: {range}", range = crate::simulation::steps::tolerance_range_text())]
    Tolerance(f64),
    /// The substeps lie outside `1..=`[`MAX_SUBSTEPS`].
    #[error("substeps {0}: must be 1 to {MAX_SUBSTEPS}")]
    Substeps(usize),
}

impl Model {
    /// The index of the parameter `which` addresses.
    fn edited_parameter(&self, which: ParameterRef<'_>) -> Result<usize, EditError> {
        match which {
            ParameterRef::Name(name) => self
                .parameter_index(name)
                .ok_or_else(|| EditError::UnknownName(name.to_string())),
            ParameterRef::Index(index) if index < self.parameters.len() => Ok(index),
            ParameterRef::Index(index) => Err(EditError::UnknownIndex {
                index,
                count: self.parameters.len(),
            }),
        }
    }

    /// The index of the parameter `which` addresses, checked to take the
    /// finite `value`.
    fn finite_edit(&self, which: ParameterRef<'_>, value: f64) -> Result<usize, EditError> {
        let i = self.edited_parameter(which)?;
        if value.is_finite() {
            Ok(i)
        } else {
            Err(EditError::NotFinite {
                name: self.parameters[i].name.clone(),
                value,
            })
        }
    }

    /// The model with the parameter `which` fixed at `value` (SI): it takes
    /// the value and loses its box, so it is not identified. The value must
    /// be finite; having no box any more, it may lie outside the old one.
    pub fn with_fixed<'a>(
        mut self,
        which: impl Into<ParameterRef<'a>>,
        value: f64,
    ) -> Result<Model, EditError> {
        let i = self.finite_edit(which.into(), value)?;
        let p = &mut self.parameters[i];
        p.value = value;
        p.bounds = None;
        Ok(self)
    }

    /// The model with the nominal value of the parameter `which` set to
    /// `value` (SI), its box kept: the value must be finite and, for an
    /// identified parameter, lie in its box.
    pub fn with_value<'a>(
        mut self,
        which: impl Into<ParameterRef<'a>>,
        value: f64,
    ) -> Result<Model, EditError> {
        let i = self.finite_edit(which.into(), value)?;
        let p = &mut self.parameters[i];
        if let Some((min, max)) = p.bounds {
            if !(min..=max).contains(&value) {
                return Err(EditError::OutsideBox {
                    name: p.name.clone(),
                    value,
                    min,
                    max,
                });
            }
        }
        p.value = value;
        Ok(self)
    }

    /// The model with the integrator's steps set: `tolerance`, if given,
    /// must lie in [`TOLERANCE_RANGE`]; `substeps`, if given, fixes the
    /// steps per sample and must be 1 to [`MAX_SUBSTEPS`]. `None` keeps
    /// what the model has.
    pub fn with_steps(
        mut self,
        tolerance: Option<f64>,
        substeps: Option<usize>,
    ) -> Result<Model, EditError> {
        if let Some(t) = tolerance {
            if !TOLERANCE_RANGE.contains(&t) {
                return Err(EditError::Tolerance(t));
            }
            self.sampling.tolerance = t;
        }
        if let Some(s) = substeps {
            if !(1..=MAX_SUBSTEPS).contains(&s) {
                return Err(EditError::Substeps(s));
            }
            self.sampling.substeps = Some(s);
        }
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::model_file::parse_model;
    use std::path::Path;

    fn knee_column() -> Model {
        let text = include_str!("../../../../examples/knee-column/model.toml");
        parse_model(text, Path::new("examples/knee-column/model.toml")).expect("valid model")
    }

    #[test]
    fn fixed_parameter_loses_its_box() {
        let m = knee_column();
        let i = m.identified()[0];
        let name = m.parameters[i].name.clone();
        let fixed = m.clone().with_fixed(name.as_str(), 2.5).unwrap();
        assert_eq!(fixed.parameters[i].value, 2.5);
        assert!(fixed.parameters[i].bounds.is_none());
        assert_eq!(fixed.identified().len(), m.identified().len() - 1);
        let by_index = m.with_fixed(i, 2.5).unwrap();
        assert_eq!(by_index.parameters[i], fixed.parameters[i]);
    }

    #[test]
    fn bad_edits_are_refused() {
        let m = knee_column();
        let i = m.identified()[0];
        let (lo, hi) = m.parameters[i].bounds.unwrap();
        assert!(matches!(
            m.clone().with_fixed("no such", 1.0),
            Err(EditError::UnknownName(_))
        ));
        let n = m.parameters.len();
        assert!(matches!(
            m.clone().with_value(n, 1.0),
            Err(EditError::UnknownIndex { .. })
        ));
        assert!(matches!(
            m.clone().with_fixed(i, f64::NAN),
            Err(EditError::NotFinite { .. })
        ));
        assert!(matches!(
            m.clone().with_value(i, hi + (hi - lo)),
            Err(EditError::OutsideBox { .. })
        ));
        let inside = m.clone().with_value(i, 0.5 * (lo + hi)).unwrap();
        assert_eq!(inside.parameters[i].bounds, Some((lo, hi)));
        assert_eq!(
            m.clone().with_steps(Some(1.0), None).unwrap_err(),
            EditError::Tolerance(1.0)
        );
        assert_eq!(
            m.clone()
                .with_steps(None, Some(MAX_SUBSTEPS + 1))
                .unwrap_err(),
            EditError::Substeps(MAX_SUBSTEPS + 1)
        );
        let stepped = m.with_steps(Some(1e-6), Some(3)).unwrap();
        assert_eq!(stepped.sampling.tolerance, 1e-6);
        assert_eq!(stepped.sampling.substeps, Some(3));
    }
}
