//! The state of a split step's column of derivatives in a located
//! switch's instant (`split_shifts`), kept in the workspace.
/// The split column's state in a step (`Workspace::shift`).
#[derive(Debug, Clone, Default)]
pub(crate) struct Shift {
    /// The index in the step's crossings of the instant the column
    /// follows, if any.
    pub(super) instant: Option<usize>,
    /// Whether the current piece ends or starts at that instant (its
    /// explicit terms are then not zero).
    pub(super) on: bool,
    /// For the current piece: `(dL/dθ*, h [a = *], h [b = *], L)`.
    pub(super) piece: (f64, f64, f64, f64),
    /// `dt*/dx` of the instant, one per column, once its piece starts.
    pub(super) rates: Vec<f64>,
    /// The excitation forces' rates at a stage.
    pub(super) forces: Vec<f64>,
}

impl Shift {
    /// No instant followed, keeping the buffers.
    pub(super) fn reset(&mut self) {
        self.instant = None;
        self.on = false;
        self.rates.clear();
    }

    /// Sets the piece `(from, to)` of the step of length h, piece number
    /// `piece` (the crossings before it), as moving with the instant or not.
    #[inline(never)]
    pub(super) fn set_piece(&mut self, piece: usize, (from, to): (f64, f64), h: f64) {
        let Some(k) = self.instant else {
            self.on = false;
            return;
        };
        let a = f64::from(u8::from(piece == k + 1));
        let b = f64::from(u8::from(piece == k));
        self.on = a + b > 0.0;
        self.piece = ((b - a) * h, a * h, b * h, (to - from) * h);
    }
}
