//! Files larger than the loader's chunks: values, errors and warnings are exactly those of a
//! small file, whatever the line endings, through `load_bytes`, through `load_file` (which streams
//! files this size through chunk buffers), and read whole into memory however large, on one
//! thread and on several whatever the machine's core count.

use bvhview::bvh::rows::CHUNK;

const HEAD: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition \
Zrotation Xrotation Yrotation\n\tEnd Site\n\t{\n\t\tOFFSET 0 5 0\n\t}\n}\nMOTION\n";

/// A take of `frames` rows (+ `extra` rows past the count) whose values encode their position.
fn take(frames: usize, extra: usize, newline: &str) -> String {
    let mut text = format!("{HEAD}Frames: {frames}\nFrame Time: 0.01\n").replace('\n', newline);
    for row in 0..frames + extra {
        text.push_str(&format!(
            "{row} {}.5 -{}.25 0 1.125 -0.0625{newline}",
            row % 97,
            row % 89
        ));
    }
    text
}

fn both(
    text: &str,
) -> (
    Result<bvhview::bvh::Bvh, String>,
    Result<bvhview::bvh::Bvh, String>,
) {
    let from_memory = bvhview::bvh::load_bytes(text.as_bytes(), "t.bvh").map_err(|e| e.to_string());
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = crate::common::scratch_folder("stream").join(format!("stream-{n}.bvh"));
    std::fs::write(&path, text).unwrap();
    let load = |threads: usize| {
        bvhview::bvh::load_file(
            &path,
            bvhview::bvh::loader::Settings {
                threads,
                ..Default::default()
            },
        )
        .map_err(|e| e.to_string().replace(&path.display().to_string(), "t.bvh"))
    };
    let from_file = bvhview::bvh::load_file(&path, Default::default())
        .map_err(|e| e.to_string().replace(&path.display().to_string(), "t.bvh"));
    // Read whole into memory, however large the file, and parsed where it lies.
    let whole = |threads: usize| {
        bvhview::bvh::load_file(
            &path,
            bvhview::bvh::loader::Settings {
                threads,
                first_read: 1 << 30,
                ..Default::default()
            },
        )
        .map_err(|e| e.to_string().replace(&path.display().to_string(), "t.bvh"))
    };
    // The same on one thread and on four, whatever this machine's core count makes the default,
    // streamed or read whole.
    for (threads, result) in [1, 4]
        .into_iter()
        .flat_map(|threads| [(threads, load(threads)), (threads, whole(threads))])
    {
        match (&from_file, result) {
            (Ok(a), Ok(b)) => {
                assert_eq!(a.skeleton, b.skeleton, "{threads} threads");
                assert_eq!(a.motion, b.motion, "{threads} threads");
                assert_eq!(a.warnings, b.warnings, "{threads} threads");
            }
            (Err(a), Err(b)) => assert_eq!(a, &b, "{threads} threads"),
            (a, b) => panic!("{threads} threads: {:?} vs {:?}", a.is_ok(), b.is_ok()),
        }
    }
    std::fs::remove_file(&path).unwrap();
    (from_memory, from_file)
}

#[test]
fn many_chunks_read_the_same_values_with_any_line_ending() {
    let frames = 4 * CHUNK / 30;
    for newline in ["\n", "\r\n", "\r"] {
        let text = take(frames, 0, newline);
        assert!(text.len() > 3 * CHUNK);
        let (memory, file) = both(&text);
        for bvh in [memory.unwrap(), file.unwrap()] {
            assert_eq!(bvh.motion.frame_count(), frames);
            for row in [0, 1, frames / 2, frames - 1] {
                let values = bvh.motion.frame(row);
                assert_eq!(
                    values,
                    &[
                        row as f32,
                        (row % 97) as f32 + 0.5,
                        -((row % 89) as f32) - 0.25,
                        0.0,
                        1.125,
                        -0.0625
                    ]
                );
            }
            assert!(bvh.warnings.is_empty());
        }
    }
}

#[test]
fn errors_deep_in_a_big_file_name_their_line_and_column() {
    let frames = 3 * CHUNK / 30;
    for newline in ["\n", "\r\n", "\r"] {
        let mut text = take(frames, 0, newline);
        // The header takes 13 lines; row 100000 is on line 14 + 100000. Break its fourth value.
        let row = 100_000;
        let needle = format!("{newline}{row} {}.5 -{}.25 0 ", row % 97, row % 89);
        let at = text.find(&needle).unwrap() + needle.len() - 2;
        text.replace_range(at..at + 1, "x");
        let line = 14 + row;
        let column = needle.len() - newline.len() - 1;
        let want = format!("t.bvh:{line}:{column}: expected a finite number, found 'x'");
        let (memory, file) = both(&text);
        assert_eq!(memory.unwrap_err(), want, "{newline:?}");
        assert_eq!(file.unwrap_err(), want, "{newline:?}");
    }
}

#[test]
fn a_short_file_and_extra_rows_are_reported_at_the_right_lines() {
    let frames = 3 * CHUNK / 30;
    let mut text = take(frames, 0, "\n");
    text = text.replace(
        &format!("Frames: {frames}"),
        &format!("Frames: {}", frames + 5),
    );
    let end_line = 14 + frames;
    let want = format!(
        "t.bvh:{end_line}:1: expected {} frames as Frames: says (line 12), found {frames}: the file ends",
        frames + 5
    );
    let (memory, file) = both(&text);
    assert_eq!(memory.unwrap_err(), want);
    assert_eq!(file.unwrap_err(), want);

    let text = take(frames, 1000, "\r\n");
    let want = format!(
        "1000 extra rows after the {frames} announced by Frames: (line 12) ignored, from line {} on",
        14 + frames
    );
    let (memory, file) = both(&text);
    for bvh in [memory.unwrap(), file.unwrap()] {
        assert_eq!(bvh.motion.frame_count(), frames);
        assert_eq!(bvh.warnings, vec![want.clone()]);
    }
}

#[test]
fn joint_names_that_look_like_the_motion_header_do_not_fool_the_streaming_loader() {
    let text = take(200, 0, "\n")
        .replace("ROOT Hips", "ROOT MOTION")
        .replace(
            "End Site\n\t{\n\t\tOFFSET 0 5 0\n\t}",
            "JOINT Frame Time x\n\t{\n\t\tOFFSET 0 5 0\n\t\tCHANNELS 0\n\t}",
        );
    assert!(text.contains("JOINT Frame Time x"));
    let (memory, file) = both(&text);
    let (memory, file) = (memory.unwrap(), file.unwrap());
    assert_eq!(file.skeleton, memory.skeleton);
    assert_eq!(file.motion, memory.motion);
    assert_eq!(file.skeleton.joints[0].name, "MOTION");
    assert_eq!(file.motion.frame_count(), 200);

    // A real error in the hierarchy is reported where it is, by both.
    let broken = take(200, 0, "\n").replace("OFFSET 0 5 0", "OFFSET 0 five 0");
    let (memory, file) = both(&broken);
    assert_eq!(
        memory.unwrap_err(),
        "t.bvh:8:12: expected OFFSET's y value (a number), found 'five'"
    );
    assert_eq!(
        file.unwrap_err(),
        "t.bvh:8:12: expected OFFSET's y value (a number), found 'five'"
    );
}

/// The values `take` writes in `row`.
fn row_values(row: usize) -> [f32; 6] {
    [
        row as f32,
        (row % 97) as f32 + 0.5,
        -((row % 89) as f32) - 0.25,
        0.0,
        1.125,
        -0.0625,
    ]
}

#[test]
fn blank_lines_anywhere_in_a_big_file_change_only_the_line_numbers() {
    // Rows are placed in the result by counting lines, so blank lines leave gaps to close, and
    // many of them use up the room before the rows do.
    let frames = 3 * CHUNK / 30;
    for every in [1, 7, 5000] {
        let plain = take(frames, 3, "\n");
        let (head, rows) = plain.split_at(plain.find("Frame Time: 0.01\n").unwrap() + 17);
        let mut text = head.to_string();
        let mut line = head.lines().count() + 1;
        let mut extra_line = 0;
        for (row, values) in rows.lines().enumerate() {
            if row == frames {
                extra_line = line;
            }
            text.push_str(values);
            text.push('\n');
            line += 1;
            if row % every == 0 {
                text.push_str(" \t\n\n");
                line += 2;
            }
        }
        let want = format!(
            "3 extra rows after the {frames} announced by Frames: (line 12) ignored, from line {extra_line} on"
        );
        let (memory, file) = both(&text);
        for bvh in [memory.unwrap(), file.unwrap()] {
            assert_eq!(bvh.motion.frame_count(), frames, "every {every}");
            for row in [0, 1, 2, frames / 3, frames / 2, frames - 2, frames - 1] {
                assert_eq!(
                    bvh.motion.frame(row),
                    &row_values(row),
                    "every {every}, row {row}"
                );
            }
            assert_eq!(bvh.warnings, vec![want.clone()], "every {every}");
        }

        // A broken value in the last row: found, at its line, wherever the room ran out.
        let last = format!("\n{} ", frames - 1);
        let at = text.find(&last).unwrap() + 1;
        text.replace_range(at..at + 1, "?");
        let line = text[..at].lines().count() + 1;
        let want = format!(
            "t.bvh:{line}:1: expected a finite number, found '?{}'",
            &last[2..last.len() - 1]
        );
        let (memory, file) = both(&text);
        assert_eq!(memory.unwrap_err(), want, "every {every}");
        assert_eq!(file.unwrap_err(), want, "every {every}");
    }
}

#[test]
fn a_row_with_the_wrong_count_names_its_own_frame_in_any_chunk() {
    // Frames are counted from 0 in this message, as `--frame` counts them. Later chunks are parsed out of order on other threads,
    // and blank lines shift where their rows are placed: neither may change the number.
    let frames = 3 * CHUNK / 30;
    for (newline, blank_every) in [("\n", 0), ("\r\n", 0), ("\r", 0), ("\n", 10)] {
        for row in [5, 20_000, 50_000, frames - 1] {
            let mut text = String::new();
            let plain = take(frames, 0, newline);
            let marker = format!("Frame Time: 0.01{newline}");
            let (head, rows) = plain.split_at(plain.find(&marker).unwrap() + marker.len());
            text.push_str(head);
            for (index, values) in rows.split_terminator(newline).enumerate() {
                if index == row {
                    // One value short: drop the last word.
                    text.push_str(&values[..values.rfind(' ').unwrap()]);
                } else {
                    text.push_str(values);
                }
                text.push_str(newline);
                if blank_every > 0 && index % blank_every == 0 {
                    text.push_str(newline);
                }
            }
            let (memory, file) = both(&text);
            let want = format!("frame {row} has 5 values, expected 6 (one per channel)");
            for error in [memory.unwrap_err(), file.unwrap_err()] {
                assert!(
                    error.ends_with(&want),
                    "{newline:?} every {blank_every}, row {row}: {error}"
                );
            }
        }
    }
}

#[test]
fn unusual_and_malformed_motion_headers_stream_to_the_same_result() {
    let frames = 3 * CHUNK / 30;
    let plain = take(frames, 0, "\n");
    // Accepted spellings stream; a malformed one is reported where it is, as from memory.
    let spaced = plain.replace("Frame Time: 0.01", "Frame  Time:\t0.01");
    let (memory, file) = both(&spaced);
    let (memory, file) = (memory.unwrap(), file.unwrap());
    assert_eq!(file.motion, memory.motion);
    assert_eq!(file.motion.frame(frames - 1), &row_values(frames - 1));
    let broken = plain.replace("Frame Time: 0.01", "FrameTime: 0.01");
    let want = "t.bvh:13:1: expected 'Frame Time:', found 'FrameTime:'";
    let (memory, file) = both(&broken);
    assert_eq!(memory.unwrap_err(), want);
    assert_eq!(file.unwrap_err(), want);
}

/// A pipe has no length up front: it streams in whole chunks, and a last row without a line end
/// or a row longer than a chunk still arrives (a pipe once read one byte per chunk and never
/// finished a line cut by the header's read).
#[test]
fn a_named_pipe_loads_the_same_as_the_file() {
    let dir = crate::common::scratch_folder("fifo");
    std::fs::create_dir_all(&dir).unwrap();
    // 3000 rows, the last without its line end.
    let rows = take(3000, 0, "\n").trim_end().to_string();
    // One row of 6 + 3 × 200 000 values: well over a chunk on one line.
    let children: String = (0..200_000)
        .map(|j| {
            format!(
                "\tJOINT j{j}\n\t{{\n\t\tOFFSET 0 1 0\n\t\tCHANNELS 3 Zrotation Xrotation \
                 Yrotation\n\t\tEnd Site\n\t\t{{\n\t\t\tOFFSET 0 1 0\n\t\t}}\n\t}}\n"
            )
        })
        .collect();
    let mut wide = HEAD.replacen("\tEnd Site", &format!("{children}\tEnd Site"), 1);
    wide.push_str("Frames: 1\nFrame Time: 0.01\n1 2 3 4 5 6");
    for j in 0..200_000 {
        wide.push_str(&format!(" {}.5 -1.25 0", j % 90));
    }
    wide.push('\n');
    assert!(wide.len() - wide.rfind("0.01").unwrap() > CHUNK);
    for (what, text) in [("rows", rows), ("one long row", wide)] {
        let fifo = dir.join("take.bvh");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.unwrap().success());
        let writer = {
            let (fifo, text) = (fifo.clone(), text.clone());
            std::thread::spawn(move || std::fs::write(fifo, text).unwrap())
        };
        let from_pipe = bvhview::bvh::load_file(&fifo, Default::default())
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        writer.join().unwrap();
        let from_memory = bvhview::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap();
        assert!(from_pipe.motion.frame_count() > 0, "{what}");
        assert_eq!(from_pipe.skeleton, from_memory.skeleton, "{what}");
        assert_eq!(from_pipe.motion, from_memory.motion, "{what}");
        // A regular file streamed through chunks (as one over 64 KB is) grows for the long row too.
        let file = dir.join("file.bvh");
        std::fs::write(&file, &text).unwrap();
        for threads in [1, 2] {
            let streamed = bvhview::bvh::load_file(
                &file,
                bvhview::bvh::loader::Settings {
                    threads,
                    first_read: 1,
                    ..Default::default()
                },
            )
            .unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(
                streamed.motion, from_memory.motion,
                "{what}, {threads} threads"
            );
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}
