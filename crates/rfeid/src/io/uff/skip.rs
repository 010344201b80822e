//! Datasets other than 58, skipped: ASCII ones up to their closing `-1`,
//! binary ones by their header's line and byte counts.
use super::binary;
use super::error::Ctx;
use super::lines::{Cursor, Line};
use super::UffError;

/// Skips a dataset other than 58, ASCII or binary.
pub fn skip(
    cur: &mut Cursor<'_>,
    head: &Line<'_>,
    is_binary: bool,
    ctx: &Ctx<'_>,
) -> Result<(), UffError> {
    if is_binary {
        let b = binary::header(head, ctx)?;
        for _ in 0..b.n_ascii {
            if cur.next_line().is_none() {
                return Err(ctx.truncated_at(
                    cur.line(),
                    cur.pos(),
                    "the file ends in the ASCII header".into(),
                ));
            }
        }
        let start = cur.pos();
        let end = start
            .checked_add(b.n_bytes)
            .and_then(|p| binary::delimiter_after(cur.bytes(), p));
        return match end {
            Some(end) => {
                cur.jump(end);
                Ok(())
            }
            None if start.saturating_add(b.n_bytes) > cur.bytes().len() => Err(ctx.truncated(
                cur.bytes(),
                cur.bytes().len(),
                format!("the binary data need {} bytes from byte {start}", b.n_bytes),
            )),
            None => Err(ctx.malformed(
                head,
                format!(
                    "no closing '    -1' after the {} bytes of binary data",
                    b.n_bytes
                ),
            )),
        };
    }
    loop {
        match cur.next_line() {
            Some(l) if l.is_delimiter() => return Ok(()),
            Some(_) => {}
            None => {
                return Err(ctx.truncated_at(
                    cur.line(),
                    cur.pos(),
                    "the file ends before the dataset's closing '    -1'".into(),
                ))
            }
        }
    }
}
