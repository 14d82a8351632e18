//! The stone's surfaces, the third of [`Stone::new`](super::Stone::new)'s builders: the
//! outline of its cut (an ellipsoid or a cabochon), what a flat back is glued on, a triplet's
//! clear cap and a colour bar's inner surface.
//!
//! Input: `[body]` and the stone's box → output: [`Surfaces`].

use glam::Vec3;

use super::{BackSurface, Cap};
use crate::geometry::{Cabochon, Ellipsoid, Outline};
use crate::scene::{Backing, Cut, Scene};

/// The surfaces of a cut stone.
pub(super) struct Surfaces {
    /// The stone's outer surface.
    pub shape: Outline,
    /// What the flat back sits on, if anything.
    pub back: Option<BackSurface>,
    /// A triplet's cap.
    pub cap: Option<Cap>,
    /// A colour bar: the domains lie only outside this inner surface.
    pub bar_inner: Option<Ellipsoid>,
    /// Centre of `bar_inner`.
    pub bar_centre: Vec3,
}

impl Surfaces {
    /// The surfaces of `scene`'s cut (`body.cut`), the stone's box of semi-axes `axes` (mm).
    pub fn new(scene: &Scene, axes: Vec3) -> Surfaces {
        let body = &scene.body;
        let s = &scene.structure;
        let girdle = (s.semi_axes_mm[0] as f32, s.semi_axes_mm[1] as f32);
        let dome = body.dome_height_mm as f32;
        let (shape, cabochon) = match body.cut {
            Cut::Ellipsoid => (Outline::Ellipsoid(Ellipsoid::new(axes)), None),
            Cut::Cabochon | Cut::Doublet | Cut::Triplet => {
                let back = if body.cut == Cut::Cabochon {
                    body.back_height_mm as f32
                } else {
                    0.0
                };
                let c = Cabochon::new(girdle.0, girdle.1, dome, back);
                (Outline::Cabochon(c), Some(c))
            }
        };
        let back = cabochon
            .filter(|c| c.flat_back() && body.backing() != Backing::None)
            .map(|c| BackSurface {
                z: c.bottom_z(),
                kind: body.backing(),
            });
        let cap = cabochon.filter(|_| body.cut == Cut::Triplet).map(|c| Cap {
            z: c.bottom_z() + body.slice_mm as f32,
            n: body.cap_index as f32,
        });
        // A colour bar: the inner surface a bar's thickness under the outer one.
        let t = body.colour_bar_mm as f32;
        let (bar_inner, bar_centre) = match (t > 0.0 && cap.is_none(), cabochon) {
            (false, _) => (None, Vec3::ZERO),
            (true, None) => {
                let inner = (axes - Vec3::splat(t)).max(Vec3::splat(1e-3));
                (Some(Ellipsoid::new(inner)), Vec3::ZERO)
            }
            (true, Some(c)) => {
                let inner = Vec3::new(girdle.0 - t, girdle.1 - t, dome - t).max(Vec3::splat(1e-3));
                (Some(Ellipsoid::new(inner)), Vec3::Z * c.girdle_z())
            }
        };
        Surfaces {
            shape,
            back,
            cap,
            bar_inner,
            bar_centre,
        }
    }
}
