//! One source file with the byte offsets of its lines, as miette reads it for a report.
//!
//! miette's own `SourceCode` for a string scans the text from its first byte to find a label's
//! line, so rendering N diagnostics of an S-byte file costs N · S. Here the line is found by
//! binary search in the line starts and only the lines a report shows are scanned, so rendering
//! costs what it shows; the result is byte for byte what miette's string source gives.

use miette::{MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents};

/// A file's display name, its text, and where each of its lines starts.
#[derive(Clone, Debug)]
pub(crate) struct SourceFile {
    name: String,
    text: String,
    /// Byte offset of every line's first byte, the first line's (0) included. Lines end where
    /// miette ends them: at `\n`, `\r\n` or a lone `\r`.
    line_starts: Vec<usize>,
}

impl SourceFile {
    pub(crate) fn new(name: String, text: String) -> SourceFile {
        let bytes = text.as_bytes();
        let mut line_starts = vec![0];
        let mut index = 0;
        while index < bytes.len() {
            match bytes[index] {
                b'\r' if bytes.get(index + 1) == Some(&b'\n') => {
                    index += 2;
                    line_starts.push(index);
                }
                b'\r' | b'\n' => {
                    index += 1;
                    line_starts.push(index);
                }
                _ => index += 1,
            }
        }
        SourceFile { name, text, line_starts }
    }

    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    pub(crate) fn text(&self) -> &str {
        &self.text
    }

    /// The index of the line holding byte `offset`.
    fn line_of(&self, offset: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= offset).saturating_sub(1)
    }
}

impl SourceCode for SourceFile {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        if span.offset() > self.text.len() {
            return Err(MietteError::OutOfBounds);
        }
        // Start scanning one line before the first line the report shows (miette's scan looks
        // at the byte before an empty span): from there it finds the window it would find
        // scanning from the start, with lines counted from there.
        let first_line = self.line_of(span.offset()).saturating_sub(context_lines_before + 1);
        let window_start = self.line_starts[first_line];
        let window = &self.text.as_bytes()[window_start..];
        let local = SourceSpan::new((span.offset() - window_start).into(), span.len());
        let contents = window.read_span(&local, context_lines_before, context_lines_after)?;
        let shown = contents.span();
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            contents.data(),
            SourceSpan::new((shown.offset() + window_start).into(), shown.len()),
            contents.line() + first_line,
            contents.column(),
            contents.line_count() + first_line,
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field miette reads, from a source.
    fn read(
        source: &dyn SourceCode,
        span: SourceSpan,
        before: usize,
        after: usize,
    ) -> Option<(Vec<u8>, usize, usize, usize, usize, usize)> {
        let contents = source.read_span(&span, before, after).ok()?;
        Some((
            contents.data().to_vec(),
            contents.span().offset(),
            contents.span().len(),
            contents.line(),
            contents.column(),
            contents.line_count(),
        ))
    }

    #[test]
    fn reads_exactly_what_miettes_string_source_reads() {
        let texts = [
            "domain d\nseed 1\ntype can { movable }\n\nproblem p {\n}\n",
            "one line without an end",
            "crlf\r\nlines\r\nand a lone\rreturn\r\n\r\nend",
            "\n\n\nstarts with blank lines\n",
            "",
            "a\n\n\nb\r\n\rc\n\n",
        ];
        for text in texts {
            let file = SourceFile::new("f.lamp".to_string(), text.to_string());
            for offset in 0..=text.len() {
                for len in [0, 1, 3] {
                    if offset + len > text.len() {
                        continue;
                    }
                    for context in [0, 1, 2, 3] {
                        let span = SourceSpan::new(offset.into(), len);
                        assert_eq!(
                            read(&file, span, context, context),
                            read(&text, span, context, context),
                            "{text:?} at {offset}+{len}, context {context}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn names_the_file() {
        let file = SourceFile::new("f.lamp".to_string(), "a\nb\n".to_string());
        let contents = file.read_span(&SourceSpan::new(2.into(), 1), 1, 1).expect("in bounds");
        assert_eq!(contents.name(), Some("f.lamp"));
        assert!(file.read_span(&SourceSpan::new(9.into(), 1), 1, 1).is_err());
    }
}
