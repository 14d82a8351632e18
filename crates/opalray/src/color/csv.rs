//! Reading a measured or computed spectrum from CSV: `wavelength_nm,value` per line.

use std::path::Path;

use crate::error::{Error, Result};

/// Parse a spectrum CSV: one `wavelength_nm,value` pair per line, any sampling, wavelengths
/// strictly increasing; blank lines and lines starting with `#` are skipped, and the first
/// remaining line may be a header (it is skipped when it starts with a letter).
/// `path` names the file in errors. Fails on fewer than two rows, a non-numeric, infinite or
/// NaN field, a line without exactly two fields, a non-positive or non-increasing wavelength.
pub fn parse_spectrum_csv(text: &str, path: &Path) -> Result<Vec<(f64, f64)>> {
    let bad = |line: usize, message: String| Error::InvalidData {
        path: path.to_path_buf(),
        message: format!("line {line}: {message}"),
    };
    let mut samples: Vec<(f64, f64)> = Vec::new();
    let mut first = true;
    // Spreadsheet exports may start with a byte-order mark.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let is_header = first && line.starts_with(|c: char| c.is_alphabetic());
        first = false;
        if is_header {
            continue;
        }
        if fields.len() != 2 {
            return Err(bad(
                line_no,
                format!(
                    "expected 2 comma-separated fields `wavelength_nm,value`, found {}",
                    fields.len()
                ),
            ));
        }
        let number = |field: &str, what: &str| -> Result<f64> {
            match field.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(bad(
                    line_no,
                    format!("{what} `{field}` is not a finite number; write e.g. `550,0.42`"),
                )),
            }
        };
        let wavelength = number(fields[0], "wavelength")?;
        let value = number(fields[1], "value")?;
        if wavelength <= 0.0 {
            return Err(bad(
                line_no,
                format!("wavelength {wavelength} nm must be positive"),
            ));
        }
        if let Some(&(previous, _)) = samples.last() {
            if wavelength <= previous {
                return Err(bad(
                    line_no,
                    format!(
                        "wavelength {wavelength} nm does not increase (previous {previous} nm); \
                         sort the rows by wavelength and remove duplicates"
                    ),
                ));
            }
        }
        samples.push((wavelength, value));
    }
    if samples.len() < 2 {
        return Err(Error::InvalidData {
            path: path.to_path_buf(),
            message: format!(
                "found {} data rows, need at least 2 lines `wavelength_nm,value`",
                samples.len()
            ),
        });
    }
    Ok(samples)
}

/// Largest spectrum CSV [`read_spectrum_csv`] reads, bytes (a million rows).
pub const MAX_CSV_BYTES: u64 = 32 << 20;

/// Read (at most [`MAX_CSV_BYTES`]) and parse a spectrum CSV file (see
/// [`parse_spectrum_csv`]).
pub fn read_spectrum_csv(path: &Path) -> Result<Vec<(f64, f64)>> {
    let text = crate::scene::read_text_limited(path, MAX_CSV_BYTES)?;
    parse_spectrum_csv(&text, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<(f64, f64)>> {
        parse_spectrum_csv(text, Path::new("s.csv"))
    }

    #[test]
    fn csv_accepts_header_comments_and_blank_lines() {
        let s = parse("# measured\nwavelength_nm,value\n\n400,0.1\n 500 , 0.5 \n").unwrap();
        assert_eq!(s, vec![(400.0, 0.1), (500.0, 0.5)]);
        assert_eq!(parse("400,1\n410,2\n").unwrap().len(), 2);
        let windows = "\u{feff}wavelength_nm,value\r\n400,1\r\n410,2\r\n";
        assert_eq!(parse(windows).unwrap(), vec![(400.0, 1.0), (410.0, 2.0)]);
    }

    #[test]
    fn csv_errors_name_the_file_and_line() {
        let cases = [
            ("", "found 0 data rows"),
            ("wavelength_nm,value\n", "found 0 data rows"),
            ("400,1\n", "found 1 data rows"),
            (
                "400,1\n390,2\n",
                "line 2: wavelength 390 nm does not increase",
            ),
            (
                "400,1\n400,2\n",
                "line 2: wavelength 400 nm does not increase",
            ),
            (
                "400,1\n410,NaN\n",
                "line 2: value `NaN` is not a finite number",
            ),
            ("400,1\n410,abc\n", "line 2: value `abc`"),
            ("400,1\nx,2\n", "line 2: wavelength `x`"),
            ("400,1,3\n", "line 1: expected 2"),
            ("-5,1\n10,1\n", "line 1: wavelength -5 nm must be positive"),
        ];
        for (text, expected) in cases {
            let err = parse(text).unwrap_err().to_string();
            assert!(err.starts_with("s.csv: "), "{err}");
            assert!(err.contains(expected), "{text:?}: {err}");
        }
    }
}
