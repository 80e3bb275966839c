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

    /// A record holding one array of 64-bit integers (key times).
    pub(super) fn i64_array(&mut self, name: &str, values: &[i64]) -> Result<(), Error> {
        let mut attributes = self.writer.new_node(name).map_err(failed)?;
        attributes
            .append_arr_i64_from_iter(ArrayAttributeEncoding::Direct, values.iter().copied())
            .map_err(failed)?;
        self.close()
    }

    /// A record holding one array of 32-bit floats (key values).
    pub(super) fn f32_array(&mut self, name: &str, values: &[f32]) -> Result<(), Error> {
        let mut attributes = self.writer.new_node(name).map_err(failed)?;
        attributes
            .append_arr_f32_from_iter(ArrayAttributeEncoding::Direct, values.iter().copied())
            .map_err(failed)?;
        self.close()
    }

    /// A record holding one array of 32-bit integers.
    pub(super) fn i32_array(&mut self, name: &str, values: &[i32]) -> Result<(), Error> {
        let mut attributes = self.writer.new_node(name).map_err(failed)?;
        attributes
            .append_arr_i32_from_iter(ArrayAttributeEncoding::Direct, values.iter().copied())
            .map_err(failed)?;
        self.close()
    }

    /// A record holding one array of 64-bit floats (a matrix).
    pub(super) fn f64_array(&mut self, name: &str, values: &[f64]) -> Result<(), Error> {
        let mut attributes = self.writer.new_node(name).map_err(failed)?;
        attributes
            .append_arr_f64_from_iter(ArrayAttributeEncoding::Direct, values.iter().copied())
            .map_err(failed)?;
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
