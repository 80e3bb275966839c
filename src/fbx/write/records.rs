//! The byte layer of FBX out: fbxcel's writer of FBX 7.4 binary records, with the few shapes
//! the scene writes (a node with values, a `P` property, an array) named for what they are.

use crate::io::error::Error;
use fbxcel::low::FbxVersion;
use fbxcel::low::v7400::ArrayAttributeEncoding;
use fbxcel::writer::v7400::binary::{AttributesWriter, FbxFooter, Writer};
use std::io::Cursor;

/// One value of a record.
#[derive(Clone, Copy, Debug)]
pub(super) enum Value<'a> {
    Bool(bool),
    I32(i32),
    I64(i64),
    F64(f64),
    Str(&'a str),
    Raw(&'a [u8]),
}

/// FBX records being written into memory.
pub(super) struct Records {
    writer: Writer<Cursor<Vec<u8>>>,
}

/// An error of fbxcel's writer (a name past 255 bytes, an array past 2^32 values).
fn failed(error: impl std::fmt::Display) -> Error {
    Error::usage(format!("cannot write FBX: {error}"))
}

impl Records {
    /// A file of FBX version 7400 (what Unreal, Unity, Maya, MotionBuilder and Blender read).
    pub(super) fn new() -> Result<Records, Error> {
        let writer = Writer::new(Cursor::new(Vec::new()), FbxVersion::V7_4).map_err(failed)?;
        Ok(Records { writer })
    }

    /// Opens the record `name` with `values`; its children follow until [`Records::close`].
    pub(super) fn open(&mut self, name: &str, values: &[Value]) -> Result<(), Error> {
        let mut attributes = self.writer.new_node(name).map_err(failed)?;
        for value in values {
            append(&mut attributes, *value)?;
        }
        Ok(())
    }

    /// Closes the record opened last.
    pub(super) fn close(&mut self) -> Result<(), Error> {
        self.writer.close_node().map_err(failed)
    }

    /// A record without children.
    pub(super) fn leaf(&mut self, name: &str, values: &[Value]) -> Result<(), Error> {
        self.open(name, values)?;
        self.close()
    }

    /// A `P` record of a `Properties70`: name, type, label, flags, then its values.
    pub(super) fn property(
        &mut self,
        name: &str,
        kind: [&str; 3],
        values: &[Value],
    ) -> Result<(), Error> {
        let mut all = vec![
            Value::Str(name),
            Value::Str(kind[0]),
            Value::Str(kind[1]),
            Value::Str(kind[2]),
        ];
        all.extend_from_slice(values);
        self.leaf("P", &all)
    }

    /// A record holding one array: key times (`i64`), key values (`f32`), indices (`i32`),
    /// vertices, weights and matrices (`f64`).
    pub(super) fn array<T: ArrayElement>(&mut self, name: &str, values: &[T]) -> Result<(), Error> {
        let mut attributes = self.writer.new_node(name).map_err(failed)?;
        T::append(&mut attributes, values).map_err(failed)?;
        self.close()
    }

    /// The file's bytes, its footer written. The footer's 16 "unknown" bytes are fbxcel's fixed
    /// ones, so that the same take always makes the same bytes.
    pub(super) fn finish(self) -> Result<Vec<u8>, Error> {
        let cursor = self
            .writer
            .finalize_and_flush(&FbxFooter::default())
            .map_err(failed)?;
        Ok(cursor.into_inner())
    }
}

fn append(
    attributes: &mut AttributesWriter<'_, Cursor<Vec<u8>>>,
    value: Value,
) -> Result<(), Error> {
    match value {
        Value::Bool(v) => attributes.append_bool(v),
        Value::I32(v) => attributes.append_i32(v),
        Value::I64(v) => attributes.append_i64(v),
        Value::F64(v) => attributes.append_f64(v),
        Value::Str(v) => attributes.append_string_direct(v),
        Value::Raw(v) => attributes.append_binary_direct(v),
    }
    .map_err(failed)
}

/// A number FBX stores in an array record; each type has its own array code.
pub(super) trait ArrayElement: Copy {
    fn append(
        attributes: &mut AttributesWriter<'_, Cursor<Vec<u8>>>,
        values: &[Self],
    ) -> Result<(), fbxcel::writer::v7400::binary::Error>;
}

macro_rules! array_element {
    ($type:ty, $append:ident) => {
        impl ArrayElement for $type {
            fn append(
                attributes: &mut AttributesWriter<'_, Cursor<Vec<u8>>>,
                values: &[Self],
            ) -> Result<(), fbxcel::writer::v7400::binary::Error> {
                attributes
                    .$append(ArrayAttributeEncoding::Direct, values.iter().copied())
                    .map(|_| ())
            }
        }
    };
}

array_element!(i32, append_arr_i32_from_iter);
array_element!(i64, append_arr_i64_from_iter);
array_element!(f32, append_arr_f32_from_iter);
array_element!(f64, append_arr_f64_from_iter);
