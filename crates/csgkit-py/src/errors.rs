//! Errors as Python exceptions: the classes live in `csgkit/_errors.py` (an exception that is
//! both a `CsgkitError` and a `ValueError` needs two bases, which Python states in one line),
//! and carry the library's messages unchanged.

use csgkit::{Error, ErrorKind as Kind};
use pyo3::prelude::*;

/// The class of `kind`.
fn class(py: Python<'_>, kind: Kind) -> PyResult<Bound<'_, PyAny>> {
    py.import("csgkit._errors")?.getattr(kind.class_name())
}

/// An exception of `kind` with `message`.
pub fn exception(kind: Kind, message: impl Into<String>) -> PyErr {
    let message = message.into();
    Python::attach(
        |py| match class(py, kind).and_then(|class| class.call1((message,))) {
            Ok(instance) => PyErr::from_value(instance),
            Err(error) => error,
        },
    )
}

/// The library's error as the exception of its kind, with its message.
pub fn from_library(error: Error) -> PyErr {
    exception(error.kind(), error.to_string())
}

/// An [`Kind::Input`] exception.
pub fn input(message: impl Into<String>) -> PyErr {
    exception(Kind::Input, message)
}

/// `error` with `prefix` before its message, if it is an [`Kind::Input`] exception (an
/// operand's arrays, say); any other exception as it is.
pub fn with_prefix(error: PyErr, prefix: &str) -> PyErr {
    Python::attach(|py| match class(py, Kind::Input) {
        Ok(class) if error.matches(py, &class).unwrap_or(false) => {
            input(format!("{prefix}: {}", error.value(py)))
        }
        _ => error,
    })
}
