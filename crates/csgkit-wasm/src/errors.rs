//! Errors as JavaScript exceptions: a `js_sys::Error` whose `name` says what the caller can do
//! about it (the classes of the Python package) and whose message is the library's, unchanged.

use csgkit::{Error, ErrorKind as Kind};

/// What every exported function returns: wasm-bindgen throws the error.
pub(crate) type Result<T> = std::result::Result<T, js_sys::Error>;

/// An exception of `kind` with `message`.
pub(crate) fn exception(kind: Kind, message: &str) -> js_sys::Error {
    let error = js_sys::Error::new(message);
    error.set_name(kind.class_name());
    error
}

/// The library's error as the exception of its kind, with its message.
pub(crate) fn from_library(error: impl Into<Error>) -> js_sys::Error {
    let error = error.into();
    exception(error.kind(), &error.to_string())
}

/// An [`Kind::Input`] exception.
pub(crate) fn input(message: &str) -> js_sys::Error {
    exception(Kind::Input, message)
}
