//! End to end under Xvfb: the viewer opens on a file, W steps a frame, J steps through the
//! recursion joint by joint (Shift+J back, Esc back to the whole picture), F, C, B, O, I and H,
//! Home and End, the timeline clicked and dragged, +, -, L, V, T and N; the window's pixels equal
//! the offscreen snapshot of each state, and Esc quits; FBX and GLB takes dropped on it (XDND,
//! as a file manager drops them) join the take shown. Needs Xvfb, xdotool and xwd
//! (scripts/test.sh installs them).

use crate::common;
use bvhview::render::draw::Style;
use bvhview::render::{Image, SnapshotOptions};
use common::*;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Ends the child when the test ends, however it ends: SIGTERM first, so that Xvfb removes its
/// lock file and socket (killed outright it left them, and after 140 runs no display number
/// was free), then SIGKILL if it is still there after 5 s.
struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        // SAFETY: signals our own child, which has not been waited for yet.
        unsafe { libc::kill(self.0.id() as libc::pid_t, libc::SIGTERM) };
        let start = Instant::now();
        while matches!(self.0.try_wait(), Ok(None)) && start.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn wait_for<T>(what: &str, timeout: Duration, mut probe: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(value) = probe() {
            return value;
        }
        assert!(start.elapsed() < timeout, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn run(display: &str, program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program)
        .args(args)
        .env("DISPLAY", display)
        .stderr(Stdio::null())
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// One window test at a time: typed keys went astray with two servers and two windows at once.
fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    static WINDOWS: std::sync::Mutex<()> = std::sync::Mutex::new(());
    WINDOWS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Starts Xvfb on a free display number.
fn start_xvfb() -> (Guard, String) {
    let number = (60..200)
        .find(|n| {
            let (socket, lock) = (format!("/tmp/.X11-unix/X{n}"), format!("/tmp/.X{n}-lock"));
            // A lock whose server is gone (killed before it could clean up) frees the number.
            let server = std::fs::read_to_string(&lock)
                .ok()
                .and_then(|pid| pid.trim().parse::<u32>().ok());
            if server.is_some_and(|pid| !Path::new(&format!("/proc/{pid}")).exists()) {
                let _ = std::fs::remove_file(&lock);
                let _ = std::fs::remove_file(&socket);
            }
            !Path::new(&socket).exists() && !Path::new(&lock).exists()
        })
        .expect("a free X display number");
    let display = format!(":{number}");
    let child = Command::new("Xvfb")
        .args([
            display.as_str(),
            "-screen",
            "0",
            "1024x768x24",
            "-nolisten",
            "tcp",
            // No reset when the last client leaves (the probe below is the first client).
            "-noreset",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("Xvfb runs (apt-get install xvfb)");
    let guard = Guard(child);
    // The socket appears before the server answers: wait for an answer.
    wait_for("Xvfb", Duration::from_secs(20), || {
        Path::new(&format!("/tmp/.X11-unix/X{number}"))
            .exists()
            .then(|| run(&display, "xdotool", &["getdisplaygeometry"]))
            .flatten()
    });
    (guard, display)
}

/// Starts the viewer on `display` with `args` in `folder`; what it prints on stderr goes to a
/// file there, for [`open_viewer`]'s message.
fn start_viewer(display: &str, folder: &Path, args: &[&Path]) -> (Guard, std::path::PathBuf) {
    let log = folder.join("viewer-stderr.txt");
    let viewer = crate::common::bvhview_command()
        .args(args)
        .current_dir(folder)
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    (Guard(viewer), log)
}

/// Starts the viewer (see [`start_viewer`]) and returns it with the id of its window, found by
/// its title (an xdotool pattern). A viewer that ends before its window shows fails the test at
/// once, with its status and what it printed; except that one the X server turned away (2 of
/// 7 full runs on a 2-core VM, never when this test ran alone) is started again, twice at most.
fn open_viewer(display: &str, folder: &Path, args: &[&Path], title: &str) -> (Guard, String) {
    let mut tries = 0;
    loop {
        tries += 1;
        let (mut viewer, log) = start_viewer(display, folder, args);
        let window = wait_for("the window", Duration::from_secs(30), || {
            if let Some(status) = viewer.0.try_wait().unwrap() {
                return Some(Err((
                    status,
                    std::fs::read_to_string(&log).unwrap_or_default(),
                )));
            }
            run(display, "xdotool", &["search", "--name", title])
                .and_then(|ids| ids.lines().next().map(|id| Ok(id.to_string())))
        });
        match window {
            Ok(window) => return (viewer, window),
            Err((_, printed)) if tries < 3 && printed.contains("cannot open the X display") => {
                eprintln!("the X server turned the viewer away; starting it again: {printed}");
                std::thread::sleep(Duration::from_millis(200));
            }
            Err((status, printed)) => {
                panic!("the viewer ended ({status}) before its window showed:\n{printed}")
            }
        }
    }
}

/// Focuses the window and makes sure typed keys reach it before the keys whose effect a test
/// checks: with both cores busy the first key after the focus was now and then lost (2 of 20
/// runs). End and Home change nothing when pressed again, so each is pressed until the title
/// says `last`, then `first` (the article's view ends it with a hint, so `contains`).
fn focus_until_keys_arrive(display: &str, window: &str, last: &str, first: &str) {
    let titled = |end: &str| {
        run(display, "xdotool", &["getwindowname", window]).is_some_and(|t| t.contains(end))
    };
    for (key, end) in [("End", last), ("Home", first)] {
        let start = Instant::now();
        loop {
            run(display, "xdotool", &["windowfocus", "--sync", window]).expect("focus");
            run(display, "xdotool", &["key", key]).unwrap_or_else(|| panic!("key {key}"));
            let pressed = Instant::now();
            while !titled(end) && pressed.elapsed() < Duration::from_secs(3) {
                std::thread::sleep(Duration::from_millis(50));
            }
            if titled(end) {
                break;
            }
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "{key} never reached the window"
            );
        }
    }
}

/// The window's pixels, read with `xwd` (32-bit ZPixmap, masks from the header).
fn capture(display: &str, window: &str) -> Image {
    let out = Command::new("xwd")
        .args(["-id", window, "-silent"])
        .env("DISPLAY", display)
        .output()
        .expect("xwd runs (apt-get install x11-apps)");
    assert!(out.status.success());
    let d = out.stdout;
    let field = |i: usize| u32::from_be_bytes(d[i * 4..i * 4 + 4].try_into().unwrap());
    let (header, width, height) = (field(0) as usize, field(4), field(5));
    let (little_endian, bits, stride) = (field(7) == 0, field(11), field(12) as usize);
    let (red, green, blue, colors) = (field(14), field(15), field(16), field(19) as usize);
    assert_eq!(bits, 32, "xwd pixels of 32 bits");
    let pixels = &d[header + colors * 12..];
    let channel = |p: u32, mask: u32| ((p & mask) >> mask.trailing_zeros()) as u8;
    let mut rgb = Vec::with_capacity((width * height * 3) as usize);
    for y in 0..height as usize {
        for x in 0..width as usize {
            let bytes: [u8; 4] = pixels[y * stride + x * 4..][..4].try_into().unwrap();
            let p = if little_endian {
                u32::from_le_bytes(bytes)
            } else {
                u32::from_be_bytes(bytes)
            };
            rgb.extend([channel(p, red), channel(p, green), channel(p, blue)]);
        }
    }
    Image { width, height, rgb }
}

/// The offscreen picture of `frame` with every option at its default: the window's first one.
fn default_snapshot(bvh: &bvhview::bvh::Bvh, frame: usize) -> Image {
    bvhview::render::snapshot(
        &bvh.skeleton,
        &bvh.motion,
        &SnapshotOptions {
            frame,
            ..SnapshotOptions::default()
        },
    )
    .unwrap()
}

#[test]
fn viewer_steps_a_frame_with_w_and_shows_the_snapshot_picture() {
    let _alone = one_at_a_time();
    let input = oracle("inputs/tiny_crlf.bvh");
    let bvh = bvhview::bvh::load_file(&input, Default::default()).unwrap();
    let snapshot = |frame| default_snapshot(&bvh, frame);

    let (_xvfb, display) = start_xvfb();
    let folder = crate::common::scratch_folder("window-one");
    let (mut viewer, window) = open_viewer(
        &display,
        &folder,
        &[&input],
        "^bvhview - tiny_crlf.bvh - frame",
    );
    let title = |frame: &str| {
        // The article's view ends its title with how to see more.
        let want =
            format!("bvhview - tiny_crlf.bvh - frame {frame} - F frames it, V studio, H keys");
        let display = display.clone();
        let window = window.clone();
        move || {
            run(&display, "xdotool", &["getwindowname", &window])
                .filter(|t| *t == want)
                .map(|_| ())
        }
    };
    wait_for(
        "frame 0 in the title",
        Duration::from_secs(30),
        title("0 (0-2)"),
    );
    let first = snapshot(0);
    let seen = wait_for("the first picture", Duration::from_secs(30), || {
        let image = capture(&display, &window);
        (image.differing_pixels(&first) == 0).then_some(image)
    });
    assert_eq!(
        (seen.width, seen.height),
        (600, 600),
        "the article's window size"
    );

    // winit reads keys through XInput2, which ignores synthetic events: focus, then type (XTEST).
    focus_until_keys_arrive(&display, &window, "frame 2 (0-2)", "frame 0 (0-2)");
    run(&display, "xdotool", &["key", "w"]).expect("key w");
    wait_for(
        "frame 1 in the title",
        Duration::from_secs(30),
        title("1 (0-2)"),
    );
    let second = snapshot(1);
    let start = Instant::now();
    let mut differing;
    loop {
        differing = capture(&display, &window).differing_pixels(&second);
        if differing == 0 || start.elapsed() > Duration::from_secs(5) {
            break;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    assert_eq!(
        differing, 0,
        "the window after W differs from the snapshot of frame 1"
    );

    // The recursion one joint at a time: J three times, Shift+J once, then Esc back to the whole
    // picture; each time the window equals the snapshot of the same step.
    let stepped = |step: Option<usize>| {
        bvhview::render::snapshot(
            &bvh.skeleton,
            &bvh.motion,
            &SnapshotOptions {
                frame: 1,
                step,
                ..SnapshotOptions::default()
            },
        )
        .unwrap()
    };
    let shows = |what: &str, want: &Image| {
        let start = Instant::now();
        loop {
            let differing = capture(&display, &window).differing_pixels(want);
            if differing == 0 {
                return;
            }
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "{what}: {differing} pixels differ from the snapshot"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    for step in 1..=3 {
        run(&display, "xdotool", &["key", "j"]).expect("key j");
        shows(&format!("step {step}"), &stepped(Some(step)));
    }
    run(&display, "xdotool", &["key", "shift+j"]).expect("key shift+j");
    shows("back to step 2", &stepped(Some(2)));
    run(&display, "xdotool", &["key", "Escape"]).expect("key Escape");
    shows("the whole picture again", &second);

    // F frames the skeleton (spheres in proportion to it), a drag turns and tilts away from it,
    // and C goes back to the article's camera.
    let framed = bvhview::render::snapshot(
        &bvh.skeleton,
        &bvh.motion,
        &SnapshotOptions {
            frame: 1,
            fit: true,
            ..SnapshotOptions::default()
        },
    )
    .unwrap();
    run(&display, "xdotool", &["key", "f"]).expect("key f");
    shows("framed with F", &framed);
    // XTEST, like the keys: no window is named (under Xvfb without a window manager the
    // window sits at 0, 0).
    for step in [
        &["mousemove", "300", "300"][..],
        &["mousedown", "1"],
        &["mousemove", "320", "330"],
        &["mousemove", "340", "360"],
        &["mouseup", "1"],
    ] {
        run(&display, "xdotool", step).expect("the mouse");
    }
    let start = Instant::now();
    while capture(&display, &window).differing_pixels(&framed) == 0 {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the drag changed nothing"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    run(&display, "xdotool", &["key", "c"]).expect("key c");
    shows("the article's camera again with C", &second);

    // B cycles the styles: sticks, both, back to the article's spheres.
    for style in [Style::Sticks, Style::Both, Style::Points] {
        run(&display, "xdotool", &["key", "b"]).expect("key b");
        let want = bvhview::render::snapshot(
            &bvh.skeleton,
            &bvh.motion,
            &SnapshotOptions {
                frame: 1,
                style,
                ..SnapshotOptions::default()
            },
        )
        .unwrap();
        shows(&format!("{style:?} after B"), &want);
    }

    // O switches the offset mode, and the title says so.
    run(&display, "xdotool", &["key", "o"]).expect("key o");
    wait_for(
        "the offset mode in the title",
        Duration::from_secs(30),
        title("1 (0-2) - position channels added to OFFSET"),
    );
    run(&display, "xdotool", &["key", "o"]).expect("key o");
    wait_for("the title back", Duration::from_secs(30), title("1 (0-2)"));

    // I shows the HUD: the picture `snapshot --hud` writes for the same state. H shows the help
    // instead, and both go away again.
    let hud_png = crate::common::scratch_folder("hud").join("hud.png");
    let made = crate::common::bvhview_command()
        .args([
            "snapshot",
            input.to_str().unwrap(),
            "--frame",
            "1",
            "--hud",
            "-q",
            "-o",
        ])
        .arg(&hud_png)
        .status()
        .unwrap();
    assert!(made.success());
    let with_hud = Image::read_png(&hud_png).unwrap();
    std::fs::remove_file(&hud_png).unwrap();
    run(&display, "xdotool", &["key", "i"]).expect("key i");
    shows("the HUD after I", &with_hud);
    run(&display, "xdotool", &["key", "h"]).expect("key h");
    let start = Instant::now();
    while capture(&display, &window).differing_pixels(&with_hud) == 0 {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "H changed nothing"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    run(&display, "xdotool", &["key", "h"]).expect("key h");
    shows("the HUD again after H", &with_hud);
    run(&display, "xdotool", &["key", "i"]).expect("key i");
    shows("no HUD after I again", &second);

    // The same pictures as `snapshot` with the same options, to within 0.1% of the pixels.
    let cli_snapshot = |args: &[&str]| {
        let png = crate::common::scratch_folder("window").join(format!(
            "snapshot{}.png",
            args.join("_").replace(['/', ' '], "")
        ));
        let made = crate::common::bvhview_command()
            .arg("snapshot")
            .arg(&input)
            .args(args)
            .args(["-q", "-o"])
            .arg(&png)
            .status()
            .unwrap();
        assert!(made.success(), "snapshot {args:?}");
        let image = Image::read_png(&png).unwrap();
        std::fs::remove_file(&png).unwrap();
        image
    };
    let close_to = |what: &str, want: &Image| {
        let start = Instant::now();
        loop {
            let seen = capture(&display, &window);
            let differing = seen.differing_pixels(want);
            if differing * 1000 <= (want.width * want.height) as usize {
                return;
            }
            if start.elapsed() > Duration::from_secs(29) {
                let _ = seen.write_png(&std::env::temp_dir().join("bvhview-window-seen.png"));
                let _ = want.write_png(&std::env::temp_dir().join("bvhview-window-want.png"));
            }
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "{what}: {differing} pixels differ from the snapshot"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    let changes = |what: &str, from: &Image| {
        let start = Instant::now();
        while capture(&display, &window).differing_pixels(from) == 0 {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "{what} changed nothing"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    let key = |name: &str| {
        run(&display, "xdotool", &["key", name]).unwrap_or_else(|| panic!("key {name}"));
    };
    let mouse = |steps: &[&[&str]]| {
        for step in steps {
            run(&display, "xdotool", step).expect("the mouse");
        }
    };

    // End and Home jump to the last and the first frame.
    key("End");
    wait_for(
        "End: the last frame",
        Duration::from_secs(30),
        title("2 (0-2)"),
    );
    key("Home");
    wait_for(
        "Home: the first frame",
        Duration::from_secs(30),
        title("0 (0-2)"),
    );

    // With the HUD, the timeline: a click at its right end seeks to the last frame, a drag back
    // to its left end to the first. The bar runs from x 12 to 588, 10 to 22 pixels up.
    key("i");
    close_to("the HUD at frame 0", &cli_snapshot(&["--hud"]));
    mouse(&[&["mousemove", "588", "584"], &["click", "1"]]);
    wait_for(
        "a click on the timeline",
        Duration::from_secs(30),
        title("2 (0-2)"),
    );
    close_to(
        "the HUD at frame 2",
        &cli_snapshot(&["--hud", "--frame", "2"]),
    );
    mouse(&[
        &["mousemove", "588", "584"],
        &["mousedown", "1"],
        &["mousemove", "300", "590"],
        &["mousemove", "0", "560"],
        &["mouseup", "1"],
    ]);
    wait_for(
        "a drag along the timeline",
        Duration::from_secs(30),
        title("0 (0-2)"),
    );
    let hud_first = cli_snapshot(&["--hud"]);
    close_to("the HUD at frame 0 again", &hud_first);

    // + and - change the speed on the HUD and back; L turns the loop off and on.
    key("plus");
    changes("+", &hud_first);
    key("minus");
    close_to("- after +", &hud_first);
    key("l");
    changes("L", &hud_first);
    key("l");
    close_to("L twice", &hud_first);
    key("i");

    // V: the studio look; T: its camera follows the root; N: the joint names. B chose the
    // spheres above, so the studio keeps them (without a choice it draws sticks too).
    key("v");
    close_to(
        "the studio look",
        &cli_snapshot(&["--look", "studio", "--style", "points"]),
    );
    key("t");
    close_to(
        "the studio look following the root",
        &cli_snapshot(&["--look", "studio", "--style", "points", "--follow"]),
    );
    key("t");
    key("v");
    key("n");
    close_to("the joint names", &cli_snapshot(&["--names"]));
    key("n");
    close_to("no names again", &cli_snapshot(&[]));

    run(&display, "xdotool", &["key", "Escape"]).expect("key Escape");
    let status = wait_for("the viewer to quit on Esc", Duration::from_secs(30), || {
        viewer.0.try_wait().unwrap()
    });
    assert!(status.success(), "exit status {status}");
    std::fs::remove_dir_all(&folder).unwrap();
}

/// Two takes side by side on one timeline equal `snapshot` of both; R loads the files again (an
/// edit shows, a broken file keeps the last good take and shows its error); P writes the picture
/// shown.
#[test]
fn viewer_shows_takes_side_by_side_reloads_and_writes_pictures() {
    let _alone = one_at_a_time();
    let dir = crate::common::scratch_folder("window-two");
    let first = dir.join("first.bvh");
    let second = dir.join("second.bvh");
    let tiny = std::fs::read_to_string(oracle("inputs/tiny_crlf.bvh")).unwrap();
    std::fs::write(&first, &tiny).unwrap();
    std::fs::write(&second, &tiny).unwrap();
    let snapshot = |files: &[&Path], extra: &[&str]| {
        let png = dir.join("want.png");
        let made = crate::common::bvhview_command()
            .arg("snapshot")
            .args(files)
            .args(extra)
            .args(["-q", "-o"])
            .arg(&png)
            .status()
            .unwrap();
        assert!(made.success());
        Image::read_png(&png).unwrap()
    };

    let (_xvfb, display) = start_xvfb();
    let (mut viewer, window) = open_viewer(
        &display,
        &dir,
        &[&first, &second],
        "^bvhview - first.bvh \\+ second.bvh - ",
    );
    let close_to = |what: &str, want: &Image| {
        let start = Instant::now();
        loop {
            let seen = capture(&display, &window);
            let differing = seen.differing_pixels(want);
            if differing * 1000 <= (want.width * want.height) as usize {
                return;
            }
            if start.elapsed() > Duration::from_secs(29) {
                let _ = seen.write_png(&std::env::temp_dir().join("bvhview-window-seen.png"));
                let _ = want.write_png(&std::env::temp_dir().join("bvhview-window-want.png"));
            }
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "{what}: {differing} pixels differ from the snapshot"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    close_to("two takes", &snapshot(&[&first, &second], &[]));
    focus_until_keys_arrive(
        &display,
        &window,
        "0.067 s of 0.067 s",
        "0.000 s of 0.067 s",
    );
    run(&display, "xdotool", &["key", "i"]).expect("key i");
    close_to(
        "two takes with the HUD and labels",
        &snapshot(&[&first, &second], &["--hud"]),
    );
    run(&display, "xdotool", &["key", "i"]).expect("key i");

    // An edit on disk shows after R: the second take's root moves 30 along x in frame 0.
    let moved = tiny.replacen("33333\r\n0.000000 ", "33333\r\n30.000000 ", 1);
    assert_ne!(moved, tiny);
    std::fs::write(&second, &moved).unwrap();
    run(&display, "xdotool", &["key", "r"]).expect("key r");
    let after_edit = snapshot(&[&first, &second], &[]);
    close_to("the edit after R", &after_edit);

    // A broken file: R keeps the last good take and shows the error line where the HUD goes.
    std::fs::write(&second, "HIERARCHY\nROOT Hips\n{\n").unwrap();
    run(&display, "xdotool", &["key", "r"]).expect("key r");
    let start = Instant::now();
    loop {
        let seen = capture(&display, &window);
        let differing = seen.differing_pixels(&after_edit);
        // Only the text differs: the takes are drawn as before. The error is wrapped between
        // words onto up to three lines of 18 pixels across the picture (9 % of it).
        if differing > 200 && differing * 10 < 360_000 {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the error line: {differing} pixels differ"
        );
        std::thread::sleep(Duration::from_millis(50));
    }

    // P writes what is shown, named after the first file and the frame, in the working folder.
    std::fs::write(&second, &moved).unwrap();
    run(&display, "xdotool", &["key", "r"]).expect("key r");
    close_to("the good file again", &after_edit);
    run(&display, "xdotool", &["key", "p"]).expect("key p");
    let written = dir.join("first_frame00000.png");
    let picture = wait_for("P's picture", Duration::from_secs(30), || {
        Image::read_png(&written).ok()
    });
    assert!(picture.differing_pixels(&after_edit) * 1000 <= 360_000);

    run(&display, "xdotool", &["key", "Escape"]).expect("key Escape");
    let status = wait_for("the viewer to quit on Esc", Duration::from_secs(30), || {
        viewer.0.try_wait().unwrap()
    });
    assert!(status.success(), "exit status {status}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Drops `files` on `window` as a file manager does, by the XDND protocol (version 5): a source
/// window of our own owns the `XdndSelection`, sends `XdndEnter` (offering `text/uri-list`) and
/// `XdndPosition`, answers the window's request for the selection with the files' `file://`
/// URIs, and sends `XdndDrop` once the window has accepted and has the list; it returns when the
/// window says `XdndFinished`, with whether it accepted the drop. xdotool cannot drag files, so
/// the test is the drag source itself.
fn drop_files(display: &str, window: &str, files: &[&Path]) -> bool {
    use x11rb::connection::Connection;
    use x11rb::protocol::Event;
    use x11rb::protocol::xproto::{
        AtomEnum, ClientMessageEvent, ConnectionExt, CreateWindowAux, EventMask, PropMode,
        SelectionNotifyEvent, WindowClass,
    };
    let target: u32 = window.parse().expect("a window id");
    let (conn, screen) = x11rb::connect(Some(display)).expect("an X connection");
    let root = conn.setup().roots[screen].root;
    let atom = |name: &str| {
        conn.intern_atom(false, name.as_bytes())
            .unwrap()
            .reply()
            .unwrap()
            .atom
    };
    let [
        aware,
        enter,
        position,
        status,
        drop,
        finished,
        selection,
        uri_list,
        copy,
    ] = [
        "XdndAware",
        "XdndEnter",
        "XdndPosition",
        "XdndStatus",
        "XdndDrop",
        "XdndFinished",
        "XdndSelection",
        "text/uri-list",
        "XdndActionCopy",
    ]
    .map(atom);
    // The window says which XDND versions it speaks: winit's says 5.
    let version = conn
        .get_property(false, target, aware, AtomEnum::ATOM, 0, 1)
        .unwrap()
        .reply()
        .unwrap();
    assert_eq!(version.value32().and_then(|mut v| v.next()), Some(5));
    let source = conn.generate_id().unwrap();
    conn.create_window(
        0,
        source,
        root,
        0,
        0,
        1,
        1,
        0,
        WindowClass::INPUT_OUTPUT,
        0,
        &CreateWindowAux::new(),
    )
    .unwrap();
    conn.set_selection_owner(source, selection, x11rb::CURRENT_TIME)
        .unwrap();
    let send = |kind: u32, data: [u32; 5]| {
        let message = ClientMessageEvent::new(32, target, kind, data);
        conn.send_event(false, target, EventMask::NO_EVENT, message)
            .unwrap();
        conn.flush().unwrap();
    };
    // Version 5 in the high byte; at most three types, listed in the message itself.
    send(enter, [source, 5 << 24, uri_list, 0, 0]);
    // The pointer over the middle of the window (root coordinates: no window manager moves it).
    send(
        position,
        [source, 0, (300 << 16) | 300, x11rb::CURRENT_TIME, copy],
    );
    let uris: String = files
        .iter()
        .map(|f| format!("file://{}\r\n", f.canonicalize().unwrap().display()))
        .collect();
    let (mut served, mut accepted, mut dropped) = (false, false, false);
    let start = Instant::now();
    loop {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the drop did not finish (served {served}, accepted {accepted}, dropped {dropped})"
        );
        let Some(event) = conn.poll_for_event().unwrap() else {
            std::thread::sleep(Duration::from_millis(10));
            continue;
        };
        match event {
            Event::SelectionRequest(request) if request.target == uri_list => {
                conn.change_property(
                    PropMode::REPLACE,
                    request.requestor,
                    request.property,
                    uri_list,
                    8,
                    uris.len() as u32,
                    uris.as_bytes(),
                )
                .unwrap();
                let notify = SelectionNotifyEvent {
                    response_type: x11rb::protocol::xproto::SELECTION_NOTIFY_EVENT,
                    sequence: 0,
                    time: request.time,
                    requestor: request.requestor,
                    selection: request.selection,
                    target: request.target,
                    property: request.property,
                };
                conn.send_event(false, request.requestor, EventMask::NO_EVENT, notify)
                    .unwrap();
                conn.flush().unwrap();
                served = true;
            }
            Event::ClientMessage(message) if message.type_ == status => {
                accepted = message.data.as_data32()[1] & 1 == 1;
            }
            Event::ClientMessage(message) if message.type_ == finished => {
                return message.data.as_data32()[1] & 1 == 1;
            }
            _ => {}
        }
        // The list reaches the window before the drop: both are sent on this one connection.
        if served && accepted && !dropped {
            send(drop, [source, 0, x11rb::CURRENT_TIME, 0, 0]);
            dropped = true;
        }
    }
}

/// An FBX take and a GLB take dropped on the window join the BVH take shown, as a
/// dropped BVH does: the title names each, nothing is said on stderr, and the window shows what
/// `snapshot` draws of the three side by side (at the angle the window started with, one take's).
#[test]
fn fbx_and_glb_takes_dropped_on_the_window_join_the_take_shown() {
    let _alone = one_at_a_time();
    let dir = crate::common::scratch_folder("window-drop");
    let bvh = data("bvh/bvh11_131_01.bvh");
    let fbx = data("fbx/bvh11_131_01.fbx");
    let glb = data("gltf/bvhpython_test_freebvh.glb");
    let (_xvfb, display) = start_xvfb();
    let (mut viewer, window) = open_viewer(
        &display,
        &dir,
        &[&bvh],
        "^bvhview - bvh11_131_01.bvh - frame 0 ",
    );
    let titled = |want: &str| {
        wait_for(want, Duration::from_secs(30), || {
            run(&display, "xdotool", &["getwindowname", &window]).filter(|t| t.starts_with(want))
        })
    };
    assert!(
        drop_files(&display, &window, &[&fbx]),
        "the FBX drop refused"
    );
    titled("bvhview - bvh11_131_01.bvh + bvh11_131_01.fbx - 0.000 s of ");
    assert!(
        drop_files(&display, &window, &[&glb]),
        "the GLB drop refused"
    );
    titled("bvhview - bvh11_131_01.bvh + bvh11_131_01.fbx + bvhpython_test_freebvh.glb - ");

    let png = dir.join("want.png");
    let made = crate::common::bvhview_command()
        .arg("snapshot")
        .args([&bvh, &fbx, &glb])
        .args(["--angle", "10", "-q", "-o"])
        .arg(&png)
        .status()
        .unwrap();
    assert!(made.success());
    let want = Image::read_png(&png).unwrap();
    let start = Instant::now();
    loop {
        let seen = capture(&display, &window);
        let differing = seen.differing_pixels(&want);
        if differing * 1000 <= (want.width * want.height) as usize {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the three takes: {differing} pixels differ from the snapshot"
        );
        std::thread::sleep(Duration::from_millis(50));
    }

    run(&display, "xdotool", &["windowfocus", "--sync", &window]).expect("focus");
    run(&display, "xdotool", &["key", "Escape"]).expect("key Escape");
    let status = wait_for("the viewer to quit on Esc", Duration::from_secs(30), || {
        viewer.0.try_wait().unwrap()
    });
    assert!(status.success(), "exit status {status}");
    let said = std::fs::read_to_string(dir.join("viewer-stderr.txt")).unwrap();
    assert!(!said.contains("error"), "{said}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--record` records what the window shows from the start, M stops and writes it, M again
/// starts another (named after the file and the frame), and Esc writes that one: each checked by
/// Debian's ffprobe and ffmpeg, its first and last pictures the snapshots of the frames shown.
#[cfg(feature = "video")]
#[test]
fn the_window_records_what_it_shows_into_an_mp4() {
    use common::video::{decoded, probe, psnr};
    let _alone = one_at_a_time();
    let input = oracle("inputs/tiny_crlf.bvh");
    let bvh = bvhview::bvh::load_file(&input, Default::default()).unwrap();
    let snapshot = |frame| default_snapshot(&bvh, frame);
    let (_xvfb, display) = start_xvfb();
    let folder = tempfile::tempdir().unwrap();
    let video = folder.path().join("recorded.mp4");
    let (mut viewer, window) = open_viewer(
        &display,
        folder.path(),
        &[&input, Path::new("--record"), &video],
        "^bvhview - tiny_crlf.bvh - frame",
    );
    let log = folder.path().join("viewer-stderr.txt");
    let said = |text: &str| {
        let text = text.to_string();
        let log = log.clone();
        move || {
            let printed = std::fs::read_to_string(&log).unwrap_or_default();
            printed.contains(&text).then_some(printed)
        }
    };
    wait_for(
        "the recording to start",
        Duration::from_secs(30),
        said("recording"),
    );
    focus_until_keys_arrive(&display, &window, "frame 2 (0-2)", "frame 0 (0-2)");
    run(&display, "xdotool", &["key", "w"]).expect("key w");
    wait_for("frame 1", Duration::from_secs(30), || {
        run(&display, "xdotool", &["getwindowname", &window]).filter(|t| t.contains("frame 1 ("))
    });
    let one = snapshot(1);
    wait_for("frame 1 drawn", Duration::from_secs(30), || {
        (capture(&display, &window).differing_pixels(&one) == 0).then_some(())
    });
    run(&display, "xdotool", &["key", "m"]).expect("key m");
    let printed = wait_for("the video written", Duration::from_secs(60), said("wrote"));
    assert!(
        printed.contains(&format!("wrote {}:", video.display())),
        "{printed}"
    );
    let probed = probe(&video);
    assert_eq!(
        (probed.codec.as_str(), probed.width, probed.height),
        ("h264", 600, 600)
    );
    let pictures = decoded(&video, (600, 600));
    assert!(pictures.len() >= 2, "{} pictures", pictures.len());
    // Every picture is one the window showed (frames 0, 2 and 1: End, Home and W may come
    // within one frame of the video, where the newest replaces the one before), the last frame 1.
    let shown = [snapshot(0), snapshot(2), one.clone()];
    for (k, picture) in pictures.iter().enumerate() {
        let nearest = shown
            .iter()
            .map(|state| psnr(picture, &state.rgb))
            .fold(0.0, f64::max);
        assert!(
            nearest >= 35.0,
            "picture {k}: {nearest:.2} dB from any frame shown"
        );
    }
    let last = psnr(pictures.last().unwrap(), &one.rgb);
    assert!(last >= 35.0, "the last picture: {last:.2} dB from frame 1");

    // M again: a second recording, written when the window closes.
    run(&display, "xdotool", &["key", "m"]).expect("key m");
    wait_for(
        "the second recording",
        Duration::from_secs(30),
        said("recording tiny_crlf_frame00001.mp4"),
    );
    run(&display, "xdotool", &["key", "Escape"]).expect("key Escape");
    let status = wait_for("the viewer to quit on Esc", Duration::from_secs(60), || {
        viewer.0.try_wait().unwrap()
    });
    assert!(status.success(), "exit status {status}");
    let second = folder.path().join("tiny_crlf_frame00001.mp4");
    let pictures = decoded(&second, (600, 600));
    assert!(!pictures.is_empty());
    assert!(psnr(&pictures[0], &one.rgb) >= 35.0);
}

/// An output asked for in the window that cannot be written (P onto a picture's name held by a
/// folder) is said at once and shown, the window goes on, and the program's exit status says
/// it when the window closes (it ended 0 before).
#[test]
fn an_output_the_window_could_not_write_fails_the_exit_status() {
    let _alone = one_at_a_time();
    let input = oracle("inputs/tiny_crlf.bvh");
    let (_xvfb, display) = start_xvfb();
    let folder = tempfile::tempdir().unwrap();
    std::fs::create_dir(folder.path().join("tiny_crlf_frame00000.png")).unwrap();
    let (mut viewer, window) = open_viewer(
        &display,
        folder.path(),
        &[&input],
        "^bvhview - tiny_crlf.bvh - frame",
    );
    focus_until_keys_arrive(&display, &window, "frame 2 (0-2)", "frame 0 (0-2)");
    run(&display, "xdotool", &["key", "p"]).expect("key p");
    let log = folder.path().join("viewer-stderr.txt");
    let printed = wait_for("the refusal", Duration::from_secs(30), || {
        let printed = std::fs::read_to_string(&log).unwrap_or_default();
        printed
            .contains("tiny_crlf_frame00000.png")
            .then_some(printed)
    });
    assert!(printed.contains("folder"), "{printed}");
    run(&display, "xdotool", &["key", "Escape"]).expect("key Escape");
    let status = wait_for("the viewer to quit on Esc", Duration::from_secs(30), || {
        viewer.0.try_wait().unwrap()
    });
    assert!(!status.success(), "exit status {status}");
}

/// `--character` puts the take on a character in the window as `snapshot` draws it
/// (the studio look: the mesh skinned, lit, casting its shadow).
#[test]
fn viewer_shows_a_take_on_a_character_as_snapshot_does() {
    let _alone = one_at_a_time();
    let dir = crate::common::scratch_folder("window-char");
    std::fs::create_dir_all(&dir).unwrap();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let walk = repo.join("tests/data/bvh/bvh11_131_01.bvh");
    let character = repo.join("tests/data/characters/capsule_mixamo.fbx");
    let png = dir.join("want.png");
    let made = crate::common::bvhview_command()
        .arg("snapshot")
        .arg(&walk)
        .arg("--character")
        .arg(&character)
        .args(["--look", "studio", "-q", "-o"])
        .arg(&png)
        .status()
        .unwrap();
    assert!(made.success());
    let want = Image::read_png(&png).unwrap();
    let (_xvfb, display) = start_xvfb();
    let (mut viewer, window) = open_viewer(
        &display,
        &dir,
        &[
            &walk,
            Path::new("--character"),
            &character,
            Path::new("--look"),
            Path::new("studio"),
        ],
        "^bvhview - bvh11_131_01.bvh - frame",
    );
    // The window's picture within 0.1 % of the snapshot's, once it has drawn it.
    wait_for(
        "the window to show the snapshot's picture of the character",
        Duration::from_secs(30),
        || {
            let differing = capture(&display, &window).differing_pixels(&want);
            (differing * 1000 <= (want.width * want.height) as usize).then_some(())
        },
    );
    let _ = viewer.0.kill();
    let _ = viewer.0.wait();
}
