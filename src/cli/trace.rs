//! `bvhview trace`: the GL calls one `display()` makes, in C, optionally explained.

use super::{FitArg, Source, View, load, resolve_up, write_text};
use crate::io::error::Error;
use crate::render::draw::Style;
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct TraceArgs {
    /// A take: .bvh, .fbx, .gltf, .glb or AMASS .npz, or an .asf skeleton (its motion with --motion).
    file: PathBuf,
    #[command(flatten)]
    source: Source,
    /// Frame to draw, from 0.
    #[arg(long, default_value_t = 0)]
    frame: usize,
    #[command(flatten)]
    view: View,
    /// Say first what the article's program does with the file (reads it as written, misreads
    /// it, rejects it or crashes on it), then indent each call by the depth of the matrix stack
    /// and say what it does: the joint, the MOTION columns it reads (the article's pFrame), what
    /// the article's flags turn, where each sphere lands.
    #[arg(long)]
    explain: bool,
    /// The language of --explain's notes.
    #[arg(long, value_enum, default_value_t, requires = "explain")]
    lang: LanguageArg,
    /// How numbers are written: printf's %f (the article's code), or apitrace's %g with the
    /// whole run from init() on, to diff against a recording of the article's program.
    #[arg(long, value_enum, default_value_t)]
    numbers: NumbersArg,
}

/// `--lang` of `trace --explain`.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
enum LanguageArg {
    /// English.
    #[default]
    En,
    /// Traditional Chinese, in the article's terms.
    Zh,
}

/// `--numbers` of `trace`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
enum NumbersArg {
    /// printf's %f, six decimals: display() only.
    #[default]
    Printf,
    /// apitrace's %.7g / %.16g, from init() through display().
    Apitrace,
}

pub(crate) fn run(mut args: TraceArgs) -> Result<ExitCode, Error> {
    args.source.up = super::UpArg::turned_when_read(args.view.up);
    use crate::render::scene::{self, Scene};
    use crate::render::trace::{Language, Numbers, Recorder};
    let language = match args.lang {
        LanguageArg::En => Language::English,
        LanguageArg::Zh => Language::Chinese,
    };
    let loaded = match load(&args.file, &args.source) {
        Ok(loaded) => loaded,
        Err(error) => {
            // What the article's program does with a file bvhview refuses is still worth a line.
            // A file refused only for its depth is read again, deeper, to compare with.
            if args.explain {
                let deeper = crate::bvh::load_file(
                    args.file.as_path(),
                    crate::bvh::loader::Settings {
                        max_depth: crate::bvh::article::EXPLAIN_MAX_DEPTH,
                        ..Default::default()
                    },
                )
                .ok();
                let written = deeper.as_ref().map(|bvh| (&bvh.skeleton, &bvh.motion));
                if let Ok(article) = crate::bvh::article::run_file(&args.file, written) {
                    let mut text = crate::render::trace::verdict_line(&article.verdict, language);
                    if let Some(stack) = &article.gl_stack {
                        text.push('\n');
                        text.push_str(&crate::render::trace::gl_stack_line(stack, language));
                    }
                    write_text(&format!("{text}\n"))?;
                }
            }
            return Err(error);
        }
    };
    let values = crate::render::frame_values(&loaded.motion, args.frame)?;
    let View {
        angle,
        style,
        fit,
        offset_mode,
        up,
        ..
    } = args.view;
    let offset_mode = offset_mode.into();
    let whole_take = fit == Some(FitArg::Take);
    let fit = fit.is_some();
    let stance = loaded.stance(offset_mode);
    let up = resolve_up(up, &stance, &args.file.display().to_string(), fit);
    let angle = angle.unwrap_or(scene::START_ANGLE);
    let style = style.map_or(Style::Points, Style::from);
    let options = crate::render::SnapshotOptions {
        frame: args.frame,
        angle,
        style,
        fit,
        offset_mode,
        up,
        whole_take,
        ..Default::default()
    };
    let camera = crate::render::camera_for(&loaded.skeleton, &loaded.motion, stance, &options)?;
    let numbers = match args.numbers {
        NumbersArg::Printf => Numbers::Printf,
        NumbersArg::Apitrace => Numbers::Apitrace,
    };
    let mut recorder = if args.explain {
        // The article's program on the same bytes (an unreadable file: no verdict line).
        let article =
            crate::bvh::article::run_file(&args.file, Some((&loaded.skeleton, &loaded.motion)))
                .ok();
        Recorder::explaining(
            numbers,
            &loaded.skeleton,
            values,
            offset_mode,
            language,
            article.as_ref(),
        )
    } else {
        Recorder::new(numbers)
    };
    if args.numbers == NumbersArg::Apitrace {
        // What a recording of the article's program holds: init, reshape, then display.
        scene::init(&mut recorder);
        scene::reshape(&mut recorder, 600, 600, &camera);
    }
    let view = Scene {
        skeleton: &loaded.skeleton,
        frame: values,
        camera,
        style,
        offset_mode,
        skin: None,
        shown: None,
        sphere_radius: scene::sphere_radius(&camera, fit),
        up,
        origin: [0.0; 3],
        scale: 1.0,
        colours: None,
    };
    scene::display(&mut recorder, &view);
    write_text(&recorder.text())?;
    Ok(ExitCode::SUCCESS)
}
