//! The kinds of error a caller decides on, each with its data: a limit (what, the limit, what
//! was found), an argument (its name), a format bvhview does not read, a file whose content
//! cannot be used. The argument a message names is data, spelled by each front end: the
//! command line writes `--max-size 10`, the library `max_size 10`.

use crate::common::{bvhview, data};
use bvhview::{Error, OpenOptions, Take};

#[test]
fn a_file_past_max_size_is_a_limit_naming_the_argument() {
    let path = data("bvh/bvhparser_simple.bvh");
    let size = std::fs::metadata(&path).unwrap().len();
    let error = Take::open_with(&path, &OpenOptions::new().max_size(10)).unwrap_err();
    match &error {
        Error::Limit {
            what, limit, found, ..
        } => assert_eq!((*what, *limit, *found), ("bytes", 10, size)),
        other => panic!("expected a limit, got {other:?}"),
    }
    let shown = path.display().to_string();
    assert_eq!(
        error.to_string(),
        format!("{shown}: {size} bytes, more than max_size 10")
    );
    assert!(error.is_the_callers());
    let out = bvhview(&["info", "--max-size", "10", &shown]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!("bvhview: {shown}: {size} bytes, more than --max-size 10\n")
    );
}

#[test]
fn an_argument_the_file_cannot_take_is_named_as_data() {
    let path = data("bvh/bvhparser_simple.bvh");
    let error = Take::open_with(&path, &OpenOptions::new().take("walk")).unwrap_err();
    assert!(
        matches!(&error, Error::InvalidArgument { name: "take", .. }),
        "{error:?}"
    );
    let shown = path.display().to_string();
    assert_eq!(
        error.to_string(),
        format!("take: {shown} holds one take (only FBX and glTF files hold several)")
    );
    let out = bvhview(&["info", "--take", "walk", &shown]);
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!("bvhview: --take: {shown} holds one take (only FBX and glTF files hold several)\n")
    );
}

#[test]
fn a_name_of_no_format_is_an_unknown_format_and_a_broken_content_is_decoding() {
    let folder = tempfile::tempdir().unwrap();
    let notes = folder.path().join("notes.txt");
    std::fs::write(&notes, "HIERARCHY\n").unwrap();
    match Take::open(&notes).unwrap_err() {
        Error::UnknownFormat { input, extension } => {
            assert_eq!(
                (input, extension.as_str()),
                (notes.display().to_string(), "txt")
            );
        }
        other => panic!("expected an unknown format, got {other:?}"),
    }
    // Bytes that start as a binary FBX and stop: the content, not the request, is wrong.
    let broken = folder.path().join("broken.fbx");
    std::fs::write(&broken, b"Kaydara FBX Binary  \x00\x1a\x00\xe8\x1c\x00\x00").unwrap();
    let error = Take::open(&broken).unwrap_err();
    match &error {
        #[cfg(feature = "fbx")]
        Error::Decoding { input, .. } => assert_eq!(*input, broken.display().to_string()),
        // A build without FBX refuses the format before reading it.
        #[cfg(not(feature = "fbx"))]
        Error::Unsupported { feature, .. } => assert_eq!(*feature, "fbx"),
        other => panic!("expected a decoding error, got {other:?}"),
    }
    assert!(error.is_the_callers());
}

#[test]
fn a_format_named_for_bytes_is_from_on_the_command_line() {
    let error = OpenOptions::new()
        .open_bytes(b"not a take at all", "<stdin>")
        .unwrap_err();
    let named: Vec<&str> = match &error {
        Error::Usage(message) => message.arguments().map(|a| a.name).collect(),
        other => panic!("expected a usage error, got {other:?}"),
    };
    assert_eq!(named, ["format"]);
    assert!(
        error
            .to_string()
            .ends_with("name its format with format bvh, fbx, gltf or glb")
    );
    let out = crate::common::bvhview_command()
        .args(["info", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .and_then(|mut child| {
            use std::io::Write;
            child
                .stdin
                .take()
                .unwrap()
                .write_all(b"not a take at all")?;
            child.wait_with_output()
        })
        .unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.ends_with("name its format with --from bvh, fbx, gltf or glb\n"),
        "{said}"
    );
}
