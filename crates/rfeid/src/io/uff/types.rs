//! What a dataset-58 record holds.
use std::fmt;

/// The ordinate data type of record 7.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrdinateType {
    /// 2: real, single precision.
    RealSingle,
    /// 4: real, double precision.
    RealDouble,
    /// 5: complex, single precision.
    ComplexSingle,
    /// 6: complex, double precision.
    ComplexDouble,
}

impl OrdinateType {
    /// From the code in record 7.
    pub fn from_code(code: i64) -> Option<Self> {
        Some(match code {
            2 => OrdinateType::RealSingle,
            4 => OrdinateType::RealDouble,
            5 => OrdinateType::ComplexSingle,
            6 => OrdinateType::ComplexDouble,
            _ => return None,
        })
    }

    /// The code in record 7.
    pub fn code(self) -> i64 {
        match self {
            OrdinateType::RealSingle => 2,
            OrdinateType::RealDouble => 4,
            OrdinateType::ComplexSingle => 5,
            OrdinateType::ComplexDouble => 6,
        }
    }

    /// Types 5 and 6.
    pub fn is_complex(self) -> bool {
        matches!(
            self,
            OrdinateType::ComplexSingle | OrdinateType::ComplexDouble
        )
    }
}

impl fmt::Display for OrdinateType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            OrdinateType::RealSingle => "real single",
            OrdinateType::RealDouble => "real double",
            OrdinateType::ComplexSingle => "complex single",
            OrdinateType::ComplexDouble => "complex double",
        };
        write!(f, "{s} ({})", self.code())
    }
}

/// The abscissa (time, frequency …) of a record.
#[derive(Debug, Clone, PartialEq)]
pub enum Abscissa {
    /// Even spacing: x_k = min + k · increment, k = 0 … count − 1.
    Even {
        /// Abscissa minimum.
        min: f64,
        /// Abscissa increment.
        increment: f64,
        /// Number of points.
        count: usize,
    },
    /// Uneven spacing: the values as stored.
    Uneven(Vec<f64>),
}

impl Abscissa {
    /// The abscissa values.
    pub fn values(&self) -> Vec<f64> {
        match self {
            Abscissa::Even {
                min,
                increment,
                count,
            } => (0..*count).map(|k| min + k as f64 * increment).collect(),
            Abscissa::Uneven(x) => x.clone(),
        }
    }
}

/// One dataset-58 function record.
#[derive(Debug, Clone, PartialEq)]
pub struct UffRecord {
    /// 1-based number among the file's dataset-58 records.
    pub number: usize,
    /// Line of the record's opening `-1`.
    pub line: usize,
    /// Stored as binary `58b`.
    pub binary: bool,
    /// ID lines 1–5, trimmed; line 1 is the record's name.
    pub id_lines: [String; 5],
    /// Function type (record 6 field 1): 0 general, 1 time response, 4 FRF …
    pub function_type: i64,
    /// Response node.
    pub response_node: i64,
    /// Response direction: ±1 … ±3 translation X, Y, Z; ±4 … ±6 rotation; 0 scalar.
    pub response_direction: i64,
    /// Reference node.
    pub reference_node: i64,
    /// Reference direction.
    pub reference_direction: i64,
    /// Ordinate data type.
    pub ordinate_type: OrdinateType,
    /// Number of points.
    pub num_points: usize,
    /// Abscissa specific data type (record 8 field 1): 17 time, 18 frequency …
    pub abscissa_data_type: i64,
    /// Ordinate specific data type (record 9 field 1): 8 displacement, 11
    /// velocity, 12 acceleration …
    pub ordinate_data_type: i64,
    /// The abscissa (for complex records with uneven spacing, as read).
    pub abscissa: Abscissa,
    /// The real ordinates; empty for complex records.
    pub values: Vec<f64>,
}

impl UffRecord {
    /// ID line 1, the record's name.
    pub fn name(&self) -> &str {
        &self.id_lines[0]
    }
}
