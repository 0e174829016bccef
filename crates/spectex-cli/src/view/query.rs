//! Request parameters: the query string parsed and every value checked, with errors that name
//! the parameter and its valid range (answered as 400).

use std::fmt;

/// An answer other than success: a status and a one-line message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct HttpError {
    /// HTTP status code.
    pub status: u16,
    /// What went wrong, naming the parameter or field.
    pub message: String,
}

impl HttpError {
    /// 400 Bad Request.
    pub(crate) fn bad(message: impl Into<String>) -> Self {
        Self {
            status: 400,
            message: message.into(),
        }
    }

    /// Another status.
    pub(crate) fn status(status: u16, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
        }
    }
}

impl fmt::Display for HttpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.status, self.message)
    }
}

/// The longest query string or parameter accepted.
const MAX_QUERY: usize = 4096;

/// A parsed query string: the parameters a route takes, each taken at most once.
#[derive(Debug)]
pub(crate) struct Query {
    pairs: Vec<(String, String, bool)>,
}

impl Query {
    /// Parses `text` (after `?`), refusing repeated names and names outside `allowed`.
    pub(crate) fn parse(text: &str, allowed: &[&str]) -> Result<Self, HttpError> {
        if text.len() > MAX_QUERY {
            return Err(HttpError::bad(format!(
                "the query is {} bytes long; at most {MAX_QUERY}",
                text.len()
            )));
        }
        let mut pairs: Vec<(String, String, bool)> = Vec::new();
        for part in text.split('&').filter(|p| !p.is_empty()) {
            let (name, value) = part.split_once('=').unwrap_or((part, ""));
            let name = decode(name)?;
            let value = decode(value)?;
            if !allowed.contains(&name.as_str()) {
                return Err(HttpError::bad(format!(
                    "unknown parameter '{}'; this request takes {}",
                    name.escape_default(),
                    allowed.join(", ")
                )));
            }
            if pairs.iter().any(|(n, _, _)| *n == name) {
                return Err(HttpError::bad(format!("parameter '{name}' is given twice")));
            }
            pairs.push((name, value, false));
        }
        Ok(Self { pairs })
    }

    /// The raw value of `name`, if given.
    pub(crate) fn text(&self, name: &str) -> Option<&str> {
        self.pairs
            .iter()
            .find(|(n, _, _)| n == name)
            .map(|(_, v, _)| v.as_str())
    }

    /// A finite number within `[min, max]`, or `default` when absent.
    pub(crate) fn f64_in(
        &self,
        name: &str,
        default: Option<f64>,
        min: f64,
        max: f64,
    ) -> Result<f64, HttpError> {
        let Some(text) = self.text(name) else {
            return default.ok_or_else(|| {
                HttpError::bad(format!(
                    "parameter '{name}' is missing; give a number in [{min}, {max}]"
                ))
            });
        };
        let v = parse_f64(name, text)?;
        if !(min..=max).contains(&v) {
            return Err(HttpError::bad(format!(
                "{name} = {} is outside its valid range [{}, {}]",
                num(v),
                num(min),
                num(max)
            )));
        }
        Ok(v)
    }

    /// A whole number within `[min, max]`, or `default` when absent.
    pub(crate) fn int_in(
        &self,
        name: &str,
        default: Option<i64>,
        min: i64,
        max: i64,
    ) -> Result<i64, HttpError> {
        let Some(text) = self.text(name) else {
            return default.ok_or_else(|| {
                HttpError::bad(format!(
                    "parameter '{name}' is missing; give a whole number in [{min}, {max}]"
                ))
            });
        };
        let v: i64 = text.trim().parse().map_err(|_| {
            HttpError::bad(format!(
                "{name} = '{}' is not a whole number; give one in [{min}, {max}]",
                text.escape_default()
            ))
        })?;
        if !(min..=max).contains(&v) {
            return Err(HttpError::bad(format!(
                "{name} = {v} is outside its valid range [{min}, {max}]"
            )));
        }
        Ok(v)
    }

    /// A flag `0` or `1`, or `default` when absent.
    pub(crate) fn flag(&self, name: &str, default: bool) -> Result<bool, HttpError> {
        match self.text(name) {
            None => Ok(default),
            Some("1" | "true") => Ok(true),
            Some("0" | "false") => Ok(false),
            Some(other) => Err(HttpError::bad(format!(
                "{name} = '{}' is not a flag; give 0 or 1",
                other.escape_default()
            ))),
        }
    }

    /// One of `choices`, or `default` when absent.
    pub(crate) fn choice<'a>(
        &self,
        name: &str,
        default: &'a str,
        choices: &[&'a str],
    ) -> Result<&'a str, HttpError> {
        match self.text(name) {
            None => Ok(default),
            Some(v) => choices.iter().copied().find(|c| *c == v).ok_or_else(|| {
                HttpError::bad(format!(
                    "{name} = '{}' is not one of {}",
                    v.escape_default(),
                    choices.join(", ")
                ))
            }),
        }
    }

    /// A session id: 1 to 64 letters, digits, `-` or `_`; `None` when absent.
    pub(crate) fn session(&self, name: &str) -> Result<Option<String>, HttpError> {
        match self.text(name) {
            None => Ok(None),
            Some(s)
                if !s.is_empty()
                    && s.len() <= 64
                    && s.bytes()
                        .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_') =>
            {
                Ok(Some(s.to_owned()))
            }
            Some(s) => Err(HttpError::bad(format!(
                "{name} = '{}' is not a session id; use 1 to 64 letters, digits, - or _",
                s.escape_default()
            ))),
        }
    }
}

/// `v` as the page and messages write it: short (`1e300`, not 300 digits).
pub(crate) fn num(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A finite number, or an error naming `name`.
pub(crate) fn parse_f64(name: &str, text: &str) -> Result<f64, HttpError> {
    let v: f64 = text.trim().parse().map_err(|_| {
        HttpError::bad(format!(
            "{name} = '{}' is not a number",
            text.escape_default()
        ))
    })?;
    if !v.is_finite() {
        return Err(HttpError::bad(format!(
            "{name} = {} is not finite; give a finite number",
            num(v)
        )));
    }
    Ok(v)
}

/// Percent-decoding (`+` is a space) into UTF-8.
fn decode(text: &str) -> Result<String, HttpError> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'+' => out.push(b' '),
            b'%' => {
                let hex = bytes
                    .get(i + 1..i + 3)
                    .and_then(|h| std::str::from_utf8(h).ok())
                    .and_then(|h| u8::from_str_radix(h, 16).ok())
                    .ok_or_else(|| HttpError::bad("the query has a malformed %-escape"))?;
                out.push(hex);
                i += 2;
            }
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8(out).map_err(|_| HttpError::bad("the query is not UTF-8"))
}
