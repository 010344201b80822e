//! The name of a column of a campaign's data or estimates: a sensor or a
//! parameter, qualified by its experiment where it has one per experiment
//! (`a_n1[low]`, `knee_ax[high]`; SPEC §5).
use std::convert::Infallible;
use std::fmt;
use std::str::FromStr;

/// A sensor's or parameter's name, with the experiment it belongs to when
/// it has one per experiment. Written `name` or `name[experiment]`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ColumnName {
    /// The sensor's or parameter's name in the model.
    pub name: String,
    /// The experiment, for a column of one experiment of several.
    pub experiment: Option<String>,
}

impl ColumnName {
    /// `name` in experiment `experiment` (`""`: a data file on its own, so
    /// no experiment).
    pub fn new(name: &str, experiment: &str) -> ColumnName {
        ColumnName {
            name: name.to_string(),
            experiment: (!experiment.is_empty()).then(|| experiment.to_string()),
        }
    }
}

impl fmt::Display for ColumnName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.experiment {
            None => f.write_str(&self.name),
            Some(e) => write!(f, "{}[{e}]", self.name),
        }
    }
}

impl FromStr for ColumnName {
    type Err = Infallible;
    /// `name[experiment]` (the last `[` opens the experiment), or `name`.
    fn from_str(s: &str) -> Result<ColumnName, Infallible> {
        Ok(match s.strip_suffix(']').and_then(|n| n.split_once('[')) {
            Some((name, e)) => ColumnName {
                name: name.to_string(),
                experiment: Some(e.to_string()),
            },
            None => ColumnName::new(s, ""),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (text, name, e) in [("a_n1", "a_n1", None), ("a_n1[low]", "a_n1", Some("low"))] {
            let c: ColumnName = text.parse().unwrap();
            assert_eq!(c.name, name);
            assert_eq!(c.experiment.as_deref(), e);
            assert_eq!(c.to_string(), text);
        }
        assert_eq!(ColumnName::new("x", "").to_string(), "x");
        assert_eq!(ColumnName::new("x", "hi").to_string(), "x[hi]");
    }
}
