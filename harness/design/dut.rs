//! [`Dut`]: a design under test, built, behind one interface whichever
//! driver it has.

use crate::design::error::{Fault, PpError};
use crate::design::pixel_proc::PixelProcessor;
use crate::design::processor::Driver;
use crate::design::spec::Design;
use crate::design::top::{FrameStats, Source, Stall, Top, TopPixel};
use golden::scene::Scene;

impl Design {
    /// Builds and resets its model, driven as its row says.
    pub fn open(&self) -> Result<Dut, PpError> {
        let model = match self.driver() {
            Driver::OnePixel => Model::OnePixel(PixelProcessor::open(self)?),
            Driver::Streams => Model::Streams(Top::open(self)?),
        };
        Ok(Dut {
            design: *self,
            model,
        })
    }
}

/// A design under test, built: whichever driver its design needs, behind
/// one interface.
pub struct Dut {
    design: Design,
    model: Model,
}

/// The driver a [`Dut`] has.
enum Model {
    OnePixel(PixelProcessor),
    Streams(Top),
}

impl Dut {
    /// The design it was built from.
    pub fn design(&self) -> Design {
        self.design
    }

    /// Resets the model and loads `scene`; refuses a scene it cannot draw
    /// (other methods, an exposure without the exponential).
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), PpError> {
        match &mut self.model {
            Model::OnePixel(p) => p.load_scene(scene),
            Model::Streams(t) => t.load_scene(scene),
        }
    }

    /// From now on, injects `fault` into every processor's register
    /// writes (`None`: off).
    pub fn set_fault(&mut self, fault: Option<Fault>) {
        match &mut self.model {
            Model::OnePixel(p) => p.set_fault(fault),
            Model::Streams(t) => t.set_fault(fault, u32::MAX),
        }
    }

    /// Cycles a pixel may take before the run stops as hung.
    pub fn set_timeout_cycles(&mut self, cycles: u64) {
        match &mut self.model {
            Model::OnePixel(p) => p.set_timeout_cycles(cycles),
            Model::Streams(t) => t.set_timeout_cycles(cycles),
        }
    }

    /// Holds the result stream back as `stall` says, seeded with `seed`;
    /// nothing for a design without a result stream.
    pub fn set_stall(&mut self, seed: u64, stall: Stall) {
        if let Model::Streams(t) = &mut self.model {
            t.set_backpressure(seed, stall);
        }
    }

    /// On a mutant model: selects mutant `id` from the next reset on.
    pub fn set_mutant(&mut self, id: u16) -> Result<(), PpError> {
        match &mut self.model {
            Model::OnePixel(p) => p.set_mutant(id),
            Model::Streams(t) => t.set_mutant(id),
        }
    }

    /// Runs the pixels `coords` (distinct, in the loaded scene) and hands
    /// each to `sink` as its result arrives, with its trace events: in
    /// order one pixel at a time, or as a streamed frame leaves. The
    /// frame cycles of one pixel at a time are the pixels' cycles back to
    /// back.
    pub fn run(
        &mut self,
        coords: &[(u32, u32)],
        sink: &mut dyn FnMut(TopPixel<'_>),
    ) -> Result<FrameStats, PpError> {
        match &mut self.model {
            Model::Streams(t) => t.run_frame(Source::Stream(coords), sink),
            Model::OnePixel(p) => {
                let mut stats = FrameStats::default();
                let mut events = Vec::new();
                for &(x, y) in coords {
                    events.clear();
                    let outcome = p.run_pixel(x, y, Some(&mut events))?;
                    stats.pixels += 1;
                    stats.pixel_cycles += outcome.cycles;
                    stats.frame_cycles += outcome.cycles;
                    stats.events += events.len() as u64;
                    stats.batches += 1;
                    sink(TopPixel {
                        x,
                        y,
                        processor: 0,
                        outcome,
                        events: &events,
                    });
                }
                Ok(stats)
            }
        }
    }

    /// The streamed driver, for what only streams have (the turn, the
    /// refused takes, the waveform window's cycles).
    pub fn streams(&mut self) -> Option<&mut Top> {
        match &mut self.model {
            Model::Streams(t) => Some(t),
            Model::OnePixel(_) => None,
        }
    }

    /// The one-pixel driver.
    pub fn one_pixel(&mut self) -> Option<&mut PixelProcessor> {
        match &mut self.model {
            Model::OnePixel(p) => Some(p),
            Model::Streams(_) => None,
        }
    }
}
