//! Errors as Python exceptions: the classes live in `csgkit/_errors.py` (an exception that is
//! both a `CsgkitError` and a `ValueError` needs two bases, which Python states in one line),
//! and carry the library's messages unchanged.

use csgkit::Error;
use csgkit::discrete::CombineError;
use csgkit::exact::BooleanError;
use csgkit::ortho::OrthoError;
use pyo3::prelude::*;

/// The exception classes of `csgkit._errors`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `CsgkitError`: an operation failed (a result without a certified f64 form, say).
    Failed,
    /// `InputError`: arrays, operands, names or options the call cannot take.
    Input,
    /// `ReadError`: a file could not be read or parsed.
    Read,
    /// `WriteError`: a file could not be written.
    Write,
    /// `CancelledError`: the progress callback returned `False`.
    Cancelled,
}

impl Kind {
    fn class_name(self) -> &'static str {
        match self {
            Kind::Failed => "CsgkitError",
            Kind::Input => "InputError",
            Kind::Read => "ReadError",
            Kind::Write => "WriteError",
            Kind::Cancelled => "CancelledError",
        }
    }

    /// The kind of a library error: what the caller did wrong, if anything.
    fn of(error: &Error) -> Kind {
        match error {
            Error::Cancelled(_) => Kind::Cancelled,
            Error::Read(_) => Kind::Read,
            Error::Write(_) => Kind::Write,
            Error::InvalidMesh(_)
            | Error::Polygon(_)
            | Error::Grid(_)
            | Error::BoxesText(_)
            | Error::Unsupported { .. }
            | Error::Boolean(BooleanError::InvalidOperand(_) | BooleanError::NoOperands)
            | Error::Combine(CombineError::Operand { .. })
            | Error::Ortho(OrthoError::NonFinite { .. } | OrthoError::MaterialCount { .. }) => {
                Kind::Input
            }
            Error::Ortho(OrthoError::Vox { .. }) => Kind::Read,
            _ => Kind::Failed,
        }
    }
}

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
    exception(Kind::of(&error), error.to_string())
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
