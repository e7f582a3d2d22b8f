//! Camera paths for flying around a mesh (`dynlod fly`, the runtime benches and tests).
//!
//! ```text
//!   orbit: circle of radius 2·diag around the centre, 15° above it, 1° per frame
//!   dolly: towards the centre and back, 4·diag → 0.3·diag → 4·diag over the frames
//!   zoom:  fixed eye at 2·diag, field of view 60° → 5° → 60° over the frames
//!   cuts:  four shots of a quarter of the frames each, 0.6·diag, 40·diag, 0.6·diag, 40·diag
//!          from the centre, 90° apart around it, each orbiting 1° per frame: three jumps
//!   still: the orbit's first view on every frame (a camera at rest)
//! ```
//!
//! Each path also has an orthographic form ([`orthographic`] of a path's view): the same eye
//! and axes, framing at the centre what the perspective view frames there, so a dolly closes
//! in as a zoom does.

use crate::view::View;

/// A camera path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraPath {
    /// Circle around the mesh, 1° per frame.
    Orbit,
    /// Towards the mesh and back.
    Dolly,
    /// Field of view narrowing and widening.
    Zoom,
    /// Jumps between close and far shots, as a game's cut scenes or a respawn make them.
    Cuts,
    /// A camera at rest: the orbit's first view on every frame.
    Still,
}

impl std::str::FromStr for CameraPath {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "orbit" => Ok(Self::Orbit),
            "dolly" => Ok(Self::Dolly),
            "zoom" => Ok(Self::Zoom),
            "cuts" => Ok(Self::Cuts),
            "still" => Ok(Self::Still),
            _ => Err(format!("unknown path {s:?} (orbit, dolly, zoom, cuts or still)")),
        }
    }
}

/// The bounding box centre and diagonal of some positions.
pub fn frame_bounds(positions: &[[f32; 3]]) -> ([f32; 3], f32) {
    let (lo, hi) = crate::mesh::bounds(positions.iter().copied());
    frame_box(lo, hi)
}

/// The centre and diagonal (at least the smallest positive float) of the box `lo`–`hi`: what
/// a camera path frames ([`GltfScene::world_bounds`](crate::io::GltfScene::world_bounds) for a
/// kept scene).
pub fn frame_box(lo: [f32; 3], hi: [f32; 3]) -> ([f32; 3], f32) {
    let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let d = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    (c, d.max(f32::MIN_POSITIVE))
}

impl CameraPath {
    /// The view at `frame` of `frames` around a mesh with bounding box `centre` and `diag`.
    pub fn view(self, frame: usize, frames: usize, centre: [f32; 3], diag: f32, viewport: (u32, u32)) -> View {
        self.view_turned(frame, frames, centre, diag, viewport, 0.0)
    }

    /// [`CameraPath::view`] turned by `turn` radians about the vertical axis through
    /// `centre`: camera k of n flying the path together, each from its own side, has
    /// `turn = k · 2π / n` (`dynlod fly --cameras`). A turn of 0 is [`CameraPath::view`].
    pub fn view_turned(
        self,
        frame: usize,
        frames: usize,
        centre: [f32; 3],
        diag: f32,
        viewport: (u32, u32),
        turn: f32,
    ) -> View {
        let phase = frame as f32 / frames.max(1) as f32; // 0 → 1 over the path
        let bounce = 0.5 - 0.5 * (2.0 * std::f32::consts::PI * phase).cos(); // 0 → 1 → 0
        let (angle, dist, fov) = match self {
            Self::Orbit => ((frame as f32).to_radians(), 2.0 * diag, 45.0),
            Self::Still => (0.0, 2.0 * diag, 45.0),
            Self::Dolly => (0.0, diag * (4.0 - 3.7 * bounce), 45.0),
            Self::Zoom => (0.0, 2.0 * diag, 60.0 - 55.0 * bounce),
            Self::Cuts => {
                let shot = (4 * frame / frames.max(1)).min(3);
                let angle = (90.0 * shot as f32 + (frame - shot * frames / 4) as f32).to_radians();
                (angle, diag * if shot % 2 == 0 { 0.6 } else { 40.0 }, 45.0)
            }
        };
        // (Added only when there is a turn: adding 0 would make a -0 angle +0.)
        let angle = if turn == 0.0 { angle } else { angle + turn };
        let elev = 15f32.to_radians();
        let eye = [
            centre[0] + dist * elev.cos() * angle.sin(),
            centre[1] + dist * elev.sin(),
            centre[2] + dist * elev.cos() * angle.cos(),
        ];
        View::perspective(eye, centre, [0.0, 1.0, 0.0], fov, viewport)
    }
}

/// `v` made orthographic, framing at `centre` what it frames there (the orthographic form of
/// a path's view: `orthographic(path.view(..), centre)`).
pub fn orthographic(v: View, centre: [f32; 3]) -> View {
    v.orthographic_at(glam::Vec3::from(v.eye).distance(glam::Vec3::from(centre)))
}
