//! What a reader or writer left out of the build says: the file, the feature, and what the
//! build can do instead.

use crate::io::error::Error;

/// The refusal of a file whose format this build has no code for (its cargo feature is off).
pub fn without(feature: &'static str, format: &'static str, file: &str) -> Error {
    Error::Unsupported {
        input: file.to_string(),
        what: format,
        feature,
    }
}
