//! What the paper's two passes report of a frame ([`TwoPassStats`], the frame's [`Report`]):
//! the light pass's energy ledger and rays, and the grown structure's void ratio; read back
//! with [`Frame::two_pass`] and, as every frame's statistics hold them, with
//! [`Frame::ledger`], [`Frame::light_rays`] and [`Frame::void_ratio`].

use serde::Serialize;

use crate::light_pass::EnergyLedger;
use crate::render::{Frame, Report};
use crate::scene::Scene;

/// What the two passes rendered beyond the image.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TwoPassStats {
    /// The light pass's energy bookkeeping (its `rays` are the light rays traced).
    pub ledger: EnergyLedger,
    /// Void ratio of the cells the passes read (void cells / inside cells), in [0, 1]: the
    /// paper's grown structure, or a stone of grains read at the cell centres.
    pub void_ratio: f64,
}

impl Report for TwoPassStats {
    /// The figures every frame's statistics hold at their top level (`void_ratio`,
    /// `light_rays`, `energy`), the two passes' own.
    fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "void_ratio": self.void_ratio,
            "light_rays": self.ledger.rays,
            "energy": self.ledger,
        })
    }

    /// None: the terminal's stage times say what the passes did.
    fn notes(&self, _scene: &Scene) -> Vec<String> {
        Vec::new()
    }

    fn clone_box(&self) -> Box<dyn Report> {
        Box::new(*self)
    }
}

impl Frame {
    /// The two passes' ledger and void ratio (`None` for a frame of another method).
    pub fn two_pass(&self) -> Option<&TwoPassStats> {
        self.report_as()
    }

    /// The light pass's energy bookkeeping: the two passes', all zero for another method's
    /// frame (no light pass).
    pub fn ledger(&self) -> EnergyLedger {
        self.two_pass()
            .map_or_else(EnergyLedger::default, |r| r.ledger)
    }

    /// Light rays the light pass traced: 0 for another method's frame.
    pub fn light_rays(&self) -> u64 {
        self.ledger().rays
    }

    /// Void ratio of the cells the paper's two passes read (void cells / inside cells);
    /// `None` for the methods that render the stone model (which read no cells).
    pub fn void_ratio(&self) -> Option<f64> {
        self.two_pass().map(|r| r.void_ratio)
    }
}
