//! The text format for boxes: one box per line, `x0 y0 z0 x1 y1 z1`.
//!
//! Numbers are separated by whitespace (commas are accepted too); `#` starts a comment that
//! runs to the end of the line; blank lines are skipped. The bounds of an axis may come in
//! either order, as everywhere in the engine. A line with another count of numbers, or a token
//! that is not a finite number, is an error naming the line (1-based).

/// A malformed line of a box text file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BoxesTextError {
    /// A line does not hold exactly six numbers.
    ///
    /// *How to fix:* write each box as `x0 y0 z0 x1 y1 z1` on its own line.
    #[error("line {line}: expected 6 numbers (x0 y0 z0 x1 y1 z1), found {found}")]
    WrongCount {
        /// The 1-based line number.
        line: usize,
        /// How many numbers the line holds.
        found: usize,
    },
    /// A token is not a finite number.
    #[error("line {line}: {token:?} is not a finite number")]
    BadNumber {
        /// The 1-based line number.
        line: usize,
        /// The offending token.
        token: String,
    },
}

/// Parses a box text file.
///
/// # Errors
/// [`BoxesTextError`] naming the first bad line.
pub fn parse_boxes(text: &str) -> Result<Vec<[f64; 6]>, BoxesTextError> {
    let mut boxes = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or_default();
        let tokens: Vec<&str> = content
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .collect();
        if tokens.is_empty() {
            continue;
        }
        if tokens.len() != 6 {
            return Err(BoxesTextError::WrongCount {
                line,
                found: tokens.len(),
            });
        }
        let mut b = [0.0; 6];
        for (slot, token) in b.iter_mut().zip(&tokens) {
            *slot = token
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| BoxesTextError::BadNumber {
                    line,
                    token: token.to_string(),
                })?;
        }
        boxes.push(b);
    }
    Ok(boxes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_blank_lines_and_commas_are_accepted() {
        let text = "# boxes\n0 0 0 1 1 1\n\n  2,2,2, 3,3,3  # second\n";
        assert_eq!(
            parse_boxes(text).unwrap(),
            [
                [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
                [2.0, 2.0, 2.0, 3.0, 3.0, 3.0]
            ]
        );
    }

    #[test]
    fn bad_lines_are_named() {
        assert_eq!(
            parse_boxes("0 0 0 1 1 1\n0 0 1 1\n"),
            Err(BoxesTextError::WrongCount { line: 2, found: 4 })
        );
        let err = parse_boxes("\n\n0 0 0 1 x 1").unwrap_err();
        assert_eq!(err.to_string(), "line 3: \"x\" is not a finite number");
        assert!(parse_boxes("0 0 0 1 1 inf").is_err());
    }
}
