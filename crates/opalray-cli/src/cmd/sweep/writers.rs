//! Where a sweep's outputs go: each staged before any work, then the frames written into
//! the contact sheet, the animation and the video as they complete.

use anyhow::Result;

use super::{Args, Plan};
use crate::outputs::{Output, Outputs};

/// The sweep's outputs, each checked and staged (a temporary file) before any work.
pub(super) struct Staged {
    pub(super) sheet: Output,
    pub(super) animation: Option<Output>,
    pub(super) stats: Option<Output>,
    pub(super) video: Option<Output>,
}

impl Staged {
    /// Check and stage every output `args` names into `outputs` (`--video` also needs
    /// ffmpeg).
    pub(super) fn add(args: &Args, outputs: &mut Outputs) -> Result<Staged> {
        let sheet = outputs.add("--sheet", &args.sheet, &["png"])?;
        let animation = match &args.animation {
            Some(path) => Some(outputs.add("--animation", path, &["gif", "png"])?),
            None => None,
        };
        let stats = match &args.stats {
            Some(path) => Some(outputs.add("--stats", path, &["json"])?),
            None => None,
        };
        let video = match &args.video {
            Some(path) => {
                let out = outputs.add("--video", path, &["mp4", "webm"])?;
                super::super::video::check_ffmpeg()?;
                Some(out)
            }
            None => None,
        };
        Ok(Staged {
            sheet,
            animation,
            stats,
            video,
        })
    }
}

/// Where the frames go as they complete: the contact sheet, and the animation and video
/// each written frame by frame to its staged file (no frame is kept).
pub(super) struct Writers {
    sheet: opalray::output::ContactSheet,
    animation: Option<opalray::output::AnimationWriter>,
    video: Option<super::super::video::VideoWriter>,
}

impl Writers {
    /// A blank sheet of `args.columns` (up to 9) a row, and the animation and video
    /// `args` asks for, opened on their staged files.
    pub(super) fn open(
        args: &Args,
        outputs: &Outputs,
        staged: &Staged,
        plan: &Plan,
    ) -> Result<Writers> {
        let (w, h) = plan.size;
        let frames = plan.angles.len();
        let columns = args.columns.unwrap_or(frames.min(9));
        let sheet = opalray::output::ContactSheet::blank(frames, w, h, columns);
        let animation = match (staged.animation, &args.animation) {
            (Some(out), Some(path)) => {
                let apng = path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("png"));
                Some(outputs.write(out, |temp| {
                    opalray::output::AnimationWriter::create(
                        temp,
                        apng,
                        frames as u32,
                        w as u32,
                        h as u32,
                        args.delay_ms,
                    )
                })?)
            }
            _ => None,
        };
        let video = match (staged.video, &args.video) {
            (Some(out), Some(path)) => Some(outputs.write(out, |temp| {
                super::super::video::VideoWriter::create(temp, path, w, h, args.delay_ms)
            })?),
            _ => None,
        };
        Ok(Writers {
            sheet,
            animation,
            video,
        })
    }

    /// Frame `k` (display codes) at `angle`: into the sheet, labelled, and the animations.
    pub(super) fn push(
        &mut self,
        (outputs, staged): (&Outputs, &Staged),
        k: usize,
        angle: f64,
        rgb8: &[u8],
        (w, h): (usize, usize),
    ) -> Result<()> {
        let label = opalray::output::sheet_label(angle);
        self.sheet.place(k, rgb8, w, h, &label);
        if let (Some(writer), Some(out)) = (&mut self.animation, staged.animation) {
            outputs.write(out, |_| writer.push(rgb8))?;
        }
        if let Some(writer) = &mut self.video {
            writer.push(rgb8)?;
        }
        Ok(())
    }

    /// Write the sheet and close the animation and the video.
    pub(super) fn finish(self, outputs: &Outputs, staged: &Staged) -> Result<()> {
        let Writers {
            sheet,
            animation,
            mut video,
        } = self;
        outputs.write(staged.sheet, |path| {
            opalray::output::write_png_rgb8(
                path,
                sheet.width as u32,
                sheet.height as u32,
                &sheet.rgb,
            )
        })?;
        drop(sheet);
        if let (Some(writer), Some(out)) = (animation, staged.animation) {
            outputs.write(out, |_| writer.finish())?;
        }
        if let Some(writer) = &mut video {
            writer.finish()?;
        }
        Ok(())
    }
}
