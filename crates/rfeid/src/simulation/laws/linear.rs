//! The linear spring `f = k δ` (eq. 2): the kernels hold it in their
//! linear part.
use super::{JointLaw, KeyDims, KeyReader, KeyRole, KeyUnit, Law, LawKey, ReadLaw};
use crate::model::Value;

/// A linear spring of stiffness k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear {
    /// Stiffness k (N/m, or N·m/rad for rotations).
    pub k: Value,
}

impl JointLaw for Linear {
    fn name(&self) -> &'static str {
        Self::NAME
    }
    fn formula(&self) -> String {
        "k δ".into()
    }
    fn keys(&self) -> Vec<LawKey> {
        vec![LawKey::new(
            "k",
            "k",
            self.k,
            KeyUnit::Stiffness,
            KeyRole::Stiffness,
        )]
    }
    fn linear_stiffness(&self, p: &[f64]) -> Option<f64> {
        Some(self.k.eval(p))
    }
    fn is_spring(&self, p: &[f64]) -> bool {
        self.k.eval(p) != 0.0
    }
}

impl ReadLaw for Linear {
    const NAME: &'static str = "linear";
    const KEYS: &'static [&'static str] = &["k"];
    const IMPLIED_BY: &'static [&'static str] = &["k"];

    /// A non-negative stiffness `k`.
    fn read<E>(keys: &mut dyn KeyReader<Error = E>) -> Result<Law, E> {
        let k = keys.required("k", KeyDims::of(keys.rotational()).stiffness)?;
        Ok(Law::Linear(Linear { k }))
    }
}
