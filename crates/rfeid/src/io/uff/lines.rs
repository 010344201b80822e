//! A cursor over the lines of a universal file that may hold binary blocks:
//! lines end at `\n` (a `\r` before it is dropped), and line numbers count
//! every `\n`, also inside skipped binary data, as a text editor would.

/// One line, without its line ending.
#[derive(Debug, Clone, Copy)]
pub struct Line<'a> {
    /// 1-based line number.
    pub number: usize,
    /// Byte offset of its first byte.
    pub offset: usize,
    /// Its bytes.
    pub text: &'a [u8],
    /// Whether a line ending follows (false for a last line cut short).
    pub complete: bool,
}

impl Line<'_> {
    /// The text, lossily decoded and trimmed.
    pub fn trimmed(&self) -> String {
        String::from_utf8_lossy(self.text).trim().to_string()
    }

    /// Whether this is a `-1` delimiter line.
    pub fn is_delimiter(&self) -> bool {
        self.text.trim_ascii() == b"-1"
    }

    /// At most 40 characters of the line, for messages.
    pub fn excerpt(&self) -> String {
        let t = self.trimmed();
        match t.char_indices().nth(40) {
            Some((i, _)) => format!("{}…", &t[..i]),
            None => t,
        }
    }
}

/// The cursor.
#[derive(Debug, Clone)]
pub struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Cursor<'a> {
    /// At the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Cursor {
            bytes,
            pos: 0,
            line: 1,
        }
    }

    /// The whole buffer.
    pub fn bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Byte offset of the next read.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// Number of the next line.
    pub fn line(&self) -> usize {
        self.line
    }

    /// The next line, or `None` at the end.
    pub fn next_line(&mut self) -> Option<Line<'a>> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let (len, advance, complete) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (i, i + 1, true),
            None => (rest.len(), rest.len(), false),
        };
        let mut text = &rest[..len];
        if let Some(t) = text.strip_suffix(b"\r") {
            text = t;
        }
        let line = Line {
            number: self.line,
            offset: self.pos,
            text,
            complete,
        };
        self.pos += advance;
        self.line += 1;
        Some(line)
    }

    /// The next line that is not blank.
    pub fn next_nonblank(&mut self) -> Option<Line<'a>> {
        loop {
            let l = self.next_line()?;
            if !l.text.trim_ascii().is_empty() {
                return Some(l);
            }
        }
    }

    /// Moves to byte `to` (not before the current position), counting the
    /// line ends passed.
    pub fn jump(&mut self, to: usize) {
        let to = to.clamp(self.pos, self.bytes.len());
        self.line += self.bytes[self.pos..to]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = to;
    }
}
