//! What Debian's ffmpeg says of a video bvhview wrote: a checker nobody here wrote (the README's
//! test command installs it; bvhview itself never runs it).

use std::path::Path;
use std::process::Command;

/// Runs a checker from Debian's ffmpeg package: the README's test command installs it.
pub fn checker(program: &str, args: &[&str]) -> Vec<u8> {
    let out = Command::new(program)
        .args(args)
        .output()
        .unwrap_or_else(|e| {
            panic!("{program}: {e} (apt-get install ffmpeg: scripts/test.sh does)")
        });
    assert!(
        out.status.success(),
        "{program} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// What ffprobe says of the video stream, decoding every frame to count them.
pub struct Probe {
    pub codec: String,
    pub width: u32,
    pub height: u32,
    pub rate: String,
    pub frames: usize,
    /// The stream's length in seconds, as the file states it.
    pub seconds: f64,
}

pub fn probe(video: &Path) -> Probe {
    let text = String::from_utf8(checker(
        "ffprobe",
        &[
            "-v",
            "error",
            "-select_streams",
            "v:0",
            "-count_frames",
            "-show_entries",
            "stream=codec_name,width,height,r_frame_rate,nb_read_frames,duration",
            "-of",
            "default=noprint_wrappers=1",
            video.to_str().unwrap(),
        ],
    ))
    .unwrap();
    let field = |name: &str| {
        text.lines()
            .find_map(|line| line.strip_prefix(&format!("{name}=")))
            .unwrap_or_else(|| panic!("ffprobe said no {name}: {text}"))
            .to_string()
    };
    Probe {
        codec: field("codec_name"),
        width: field("width").parse().unwrap(),
        height: field("height").parse().unwrap(),
        rate: field("r_frame_rate"),
        frames: field("nb_read_frames").parse().unwrap(),
        seconds: field("duration").parse().unwrap(),
    }
}

/// Every frame ffmpeg decodes, as RGB bytes of `width × height` (its own conversion from the
/// stream's YUV, cut to the size asked where the video is a pixel larger).
pub fn decoded(video: &Path, (width, height): (u32, u32)) -> Vec<Vec<u8>> {
    let filter = format!("format=rgb24,crop={width}:{height}:0:0");
    let bytes = checker(
        "ffmpeg",
        &[
            "-v",
            "error",
            "-i",
            video.to_str().unwrap(),
            "-vf",
            &filter,
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgb24",
            "-",
        ],
    );
    let size = width as usize * height as usize * 3;
    assert_eq!(bytes.len() % size, 0);
    bytes.chunks_exact(size).map(<[u8]>::to_vec).collect()
}

/// Peak signal to noise ratio of `a` against `b` over all three colours, in dB.
pub fn psnr(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let squared: f64 = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).powi(2))
        .sum();
    let mse = squared / a.len() as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}
