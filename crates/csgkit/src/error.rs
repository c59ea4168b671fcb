//! The crate's one error type, [`Error`], re-exported at the crate root. It sits at the
//! top of the library with the engine facade: it names every module's error, and no module
//! below uses it.

use crate::csg::CsgError;
use crate::csg::openscad::OpenScadError;
use crate::csg::scene::SceneError;
use crate::discrete::{CombineError, DiscretizeError, GridError, OpError};
use crate::exact::{BooleanError, SplitError};
use crate::io::{ReadError, WriteError};
use crate::mesh::{InvalidMesh, PolygonError};
use crate::ortho::{BoxFileError, BoxesTextError, OrthoError};
use crate::progress::Cancelled;

/// The crate's one error type: what the engine facade returns, and what any caller
/// that mixes the crate's functions (the command line, the bindings) can use.
///
/// Each module keeps its own `thiserror` enum, beside the code that finds the problem and
/// naming where it is (file, line, vertex, face, box, operand); [`Error`] wraps each one
/// transparently, so the message is the module's and `?` converts any of them. A
/// cancellation is always [`Error::Cancelled`], whichever engine noticed it: the conversions
/// lift it out of the module errors, so a caller tests for it in one place.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The operation was cancelled through its [`Progress`](crate::Progress).
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
    /// A mesh file could not be read.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A mesh file could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// Mesh parts break the mesh invariants.
    #[error(transparent)]
    InvalidMesh(#[from] InvalidMesh),
    /// A polygon cannot be triangulated.
    #[error(transparent)]
    Polygon(#[from] PolygonError),
    /// The exact engine refused an operand or could not certify its result.
    #[error(transparent)]
    Boolean(BooleanError),
    /// One triangle could not be split exactly.
    #[error(transparent)]
    Split(#[from] SplitError),
    /// The orthogonal engine refused its boxes, or a `.vox` file.
    #[error(transparent)]
    Ortho(OrthoError),
    /// A box text file is malformed.
    #[error(transparent)]
    BoxesText(#[from] BoxesTextError),
    /// A box file (a `.vox` model or box text) could not be read.
    #[error(transparent)]
    BoxFile(#[from] BoxFileError),
    /// Cell sizes make no grid of the discrete engine.
    #[error(transparent)]
    Grid(#[from] GridError),
    /// A mesh could not be discretised.
    #[error(transparent)]
    Discretize(DiscretizeError),
    /// An operand of the discrete engine could not be discretised.
    #[error(transparent)]
    Combine(CombineError),
    /// Solids of the discrete engine on different grids.
    #[error(transparent)]
    DiscreteOp(#[from] OpError),
    /// A CSG tree could not be evaluated.
    #[error(transparent)]
    Csg(CsgError),
    /// A JSON scene is malformed.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// An OpenSCAD `.csg` file is malformed or uses an unsupported node.
    #[error(transparent)]
    OpenScad(#[from] OpenScadError),
    /// The engine does not compute this operation, or on these operands.
    ///
    /// *What to try*: another engine; the exact engine computes every operation on every
    /// closed mesh.
    #[error("the {engine} engine {reason}")]
    Unsupported {
        /// The engine's name.
        engine: &'static str,
        /// What it does not do, completing "the … engine …".
        reason: String,
    },
}

/// `From` for an engine error with a `Cancelled(Cancelled)` variant: a cancellation becomes
/// [`Error::Cancelled`], anything else the wrapping variant.
macro_rules! from_engine_error {
    ($($error:ident => $variant:ident),* $(,)?) => {$(
        impl From<$error> for Error {
            fn from(error: $error) -> Self {
                match error {
                    $error::Cancelled(cancelled) => Error::Cancelled(cancelled),
                    error => Error::$variant(error),
                }
            }
        }
    )*};
}

from_engine_error! {
    BooleanError => Boolean,
    OrthoError => Ortho,
    DiscretizeError => Discretize,
    CombineError => Combine,
}

/// What a caller can do about an [`Error`]: the one classification the bindings raise as
/// their error classes (the Python package's `csgkit.CsgkitError` and its subclasses, the
/// JavaScript module's error `name`s).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ErrorKind {
    /// An operation failed on valid input (a result without a certified f64 form, say).
    Failed,
    /// Arrays, operands, names or options the call cannot take.
    Input,
    /// A file, or bytes, that could not be read as a mesh or voxel model.
    Read,
    /// A file that could not be written, or a mesh its format cannot hold.
    Write,
    /// The run was cancelled.
    Cancelled,
}

impl ErrorKind {
    /// The name of the bindings' error class: `CsgkitError`, `InputError`, `ReadError`,
    /// `WriteError` or `CancelledError`.
    pub fn class_name(self) -> &'static str {
        match self {
            ErrorKind::Failed => "CsgkitError",
            ErrorKind::Input => "InputError",
            ErrorKind::Read => "ReadError",
            ErrorKind::Write => "WriteError",
            ErrorKind::Cancelled => "CancelledError",
        }
    }
}

impl Error {
    /// What the caller can do about this error, if anything.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::Cancelled(_) => ErrorKind::Cancelled,
            Error::Read(_) => ErrorKind::Read,
            Error::Write(_) => ErrorKind::Write,
            Error::InvalidMesh(_)
            | Error::Polygon(_)
            | Error::Grid(_)
            | Error::BoxesText(_)
            | Error::BoxFile(BoxFileError::ModelOfText)
            | Error::Unsupported { .. }
            | Error::Boolean(BooleanError::InvalidOperand(_) | BooleanError::NoOperands)
            | Error::Combine(CombineError::Operand { .. })
            | Error::Ortho(OrthoError::NonFinite { .. } | OrthoError::MaterialCount { .. }) => {
                ErrorKind::Input
            }
            Error::Ortho(OrthoError::Vox { .. }) | Error::BoxFile(_) => ErrorKind::Read,
            _ => ErrorKind::Failed,
        }
    }
}

impl From<CsgError> for Error {
    fn from(error: CsgError) -> Self {
        match error {
            CsgError::Boolean {
                error: BooleanError::Cancelled(cancelled),
                ..
            } => Error::Cancelled(cancelled),
            error => Error::Csg(error),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cancellation_is_one_variant_from_every_engine() {
        let lifted = [
            Error::from(BooleanError::Cancelled(Cancelled)),
            Error::from(OrthoError::Cancelled(Cancelled)),
            Error::from(DiscretizeError::Cancelled(Cancelled)),
            Error::from(CombineError::Cancelled(Cancelled)),
            Error::from(CsgError::Boolean {
                leaf: None,
                error: BooleanError::Cancelled(Cancelled),
            }),
        ];
        for error in lifted {
            assert!(matches!(error, Error::Cancelled(Cancelled)), "{error:?}");
            assert_eq!(error.to_string(), "cancelled");
        }
    }

    #[test]
    fn messages_are_the_modules_own() {
        let error = BooleanError::NoOperands;
        assert_eq!(Error::from(error.clone()).to_string(), error.to_string());
        let error = GridError::BadCell(-1.0);
        assert_eq!(Error::from(error.clone()).to_string(), error.to_string());
    }
}
