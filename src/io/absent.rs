//! What a reader or writer left out of the build says: the file, the feature, and what the
//! build can do instead.

use crate::io::error::Error;

/// The refusal of a file whose format this build has no code for (its cargo feature is off).
pub fn without(feature: &str, format: &str, file: &str) -> Error {
    Error::Usage(format!(
        "{file}: this bvhview was built without {format} (cargo feature `{feature}`); \
         build it with `--features {feature}`"
    ))
}
