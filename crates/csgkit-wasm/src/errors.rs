//! Errors as JavaScript exceptions: a `js_sys::Error` whose `name` says what the caller can do
//! about it (the classes of the Python package) and whose message is the library's, unchanged.

use csgkit::Error;
use csgkit::discrete::CombineError;
use csgkit::exact::BooleanError;
use csgkit::ortho::OrthoError;

/// What every exported function returns: wasm-bindgen throws the error.
pub(crate) type Result<T> = std::result::Result<T, js_sys::Error>;

/// The kinds of error, named as the Python package's exception classes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `CsgkitError`: an operation failed (a result without a certified f64 form, say).
    Failed,
    /// `InputError`: arrays, operands, names or options the call cannot take.
    Input,
    /// `ReadError`: bytes that are not a mesh or voxel file.
    Read,
    /// `WriteError`: a mesh the format cannot hold.
    Write,
    /// `CancelledError`: the progress callback returned `false`.
    Cancelled,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Failed => "CsgkitError",
            Kind::Input => "InputError",
            Kind::Read => "ReadError",
            Kind::Write => "WriteError",
            Kind::Cancelled => "CancelledError",
        }
    }

    /// The kind of a library error: what the caller did wrong, if anything (the Python
    /// package's classification).
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

/// An exception of `kind` with `message`.
pub(crate) fn exception(kind: Kind, message: &str) -> js_sys::Error {
    let error = js_sys::Error::new(message);
    error.set_name(kind.name());
    error
}

/// The library's error as the exception of its kind, with its message.
pub(crate) fn from_library(error: impl Into<Error>) -> js_sys::Error {
    let error = error.into();
    exception(Kind::of(&error), &error.to_string())
}

/// An [`Kind::Input`] exception.
pub(crate) fn input(message: &str) -> js_sys::Error {
    exception(Kind::Input, message)
}
