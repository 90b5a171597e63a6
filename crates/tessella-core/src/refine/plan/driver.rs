//! The per-frame driver of an instanced renderer whose levels change every frame: what the
//! wgpu, wasm and Bevy hosts and the viewer each did around [`instanced::frame_instances`]
//! (the LOD's levels, then the records and instances), done once here.

use super::instanced::{self, FrameInstances, PartTable};
use super::levels::{Lod, Spacing};
use super::lod;
use super::surface::{Frame, Surface};
use crate::error::RefineError;
use std::sync::Arc;

/// An instanced draw's state: the part table of its spacing (built once, shareable between
/// surfaces), and the latest levels with the records and instances made from them.
///
/// ```
/// use tessella_core::refine::{InstancedDriver, Lod, Spacing, Surface, SurfaceOptions};
/// use tessella_core::samples;
/// let mesh = samples::icosphere(1);
/// let surface = Surface::new(&mesh, &SurfaceOptions::new(tessella_core::Scheme::Pn))?;
/// let frame = surface.frame(&mesh)?;
/// let mut driver = InstancedDriver::new(Spacing::FractionalOdd);
/// driver.update(&surface, &frame, &Lod::Tolerance { max_deviation: 0.01 })?;
/// let drawn = driver.frame();
/// assert_eq!(drawn.records.len(), mesh.face_count() * tessella_core::refine::instanced::RECORD_WORDS);
/// // Each draw is a part of the table, drawn once per instance in its range.
/// let (codes, indices) = driver.part_vertices(drawn.draws[0].part);
/// assert!(!codes.is_empty() && indices.len() % 3 == 0);
/// # Ok::<(), tessella_core::RefineError>(())
/// ```
#[derive(Debug, Clone)]
pub struct InstancedDriver {
    table: Arc<PartTable>,
    frame: FrameInstances,
    edge_levels: Vec<f32>,
    face_minimums: Option<Vec<f32>>,
}

impl InstancedDriver {
    /// A driver with its own part table for `spacing`.
    pub fn new(spacing: Spacing) -> InstancedDriver {
        InstancedDriver::with_table(Arc::new(PartTable::new(spacing)))
    }

    /// A driver drawing with `table` (one table serves every surface of its spacing).
    pub fn with_table(table: Arc<PartTable>) -> InstancedDriver {
        InstancedDriver {
            table,
            frame: FrameInstances::default(),
            edge_levels: Vec::new(),
            face_minimums: None,
        }
    }

    /// The parts this driver draws.
    pub fn table(&self) -> &Arc<PartTable> {
        &self.table
    }

    /// The spacing of its parts.
    pub fn spacing(&self) -> Spacing {
        self.table.spacing
    }

    /// Part `part` as a small indexed mesh of point codes ([`PartTable::part_vertices`]).
    pub fn part_vertices(&self, part: u32) -> (Vec<u32>, Vec<u32>) {
        self.table.part_vertices(part)
    }

    /// Levels given by the caller: one per unique edge of `surface` (`Topology::edges` order,
    /// as `Levels::PerEdge`), optionally a minimum inner level per face. Makes the records and
    /// instances of the next draws; on an error the previous ones stay.
    pub fn set_levels(
        &mut self,
        surface: &Surface,
        edge_levels: &[f32],
        face_minimums: Option<&[f32]>,
    ) -> Result<&FrameInstances, RefineError> {
        self.make_frame(surface, edge_levels, face_minimums)?;
        self.edge_levels.clear();
        self.edge_levels.extend_from_slice(edge_levels);
        self.face_minimums = face_minimums.map(<[f32]>::to_vec);
        Ok(&self.frame)
    }

    /// The records and instances of the levels, kept as the frame; on an error nothing changes.
    fn make_frame(
        &mut self,
        surface: &Surface,
        edge_levels: &[f32],
        face_minimums: Option<&[f32]>,
    ) -> Result<(), RefineError> {
        let topology = surface.topology();
        self.frame = instanced::frame_instances(
            &self.table,
            topology,
            surface.triangles(),
            &topology.position_ids,
            edge_levels,
            face_minimums,
        )?;
        Ok(())
    }

    /// The levels `lod` gives on `frame` (a frame of `surface`: a camera that moves or a mesh
    /// that deforms gives new levels), then [`InstancedDriver::set_levels`].
    pub fn update(
        &mut self,
        surface: &Surface,
        frame: &Frame,
        lod: &Lod,
    ) -> Result<&FrameInstances, RefineError> {
        let (edges, faces) = self.levels(surface, frame, lod)?;
        self.make_frame(surface, &edges, faces.as_deref())?;
        // The LOD's own vectors are kept, not copied.
        self.edge_levels = edges;
        self.face_minimums = faces;
        Ok(&self.frame)
    }

    /// The levels `lod` gives on `frame`, per edge and per face, without drawing them (a host
    /// that adjusts them first, then calls [`InstancedDriver::set_levels`]).
    pub fn levels(
        &self,
        surface: &Surface,
        frame: &Frame,
        lod: &Lod,
    ) -> Result<(Vec<f32>, Option<Vec<f32>>), RefineError> {
        surface.check_frame(frame)?;
        lod::levels(frame.mesh(), surface.topology(), frame.nets(), lod)
    }

    /// The records, instances and draws of the latest levels.
    pub fn frame(&self) -> &FrameInstances {
        &self.frame
    }

    /// The latest per-edge levels.
    pub fn edge_levels(&self) -> &[f32] {
        &self.edge_levels
    }

    /// The latest per-face minimum inner levels, where the LOD gave them.
    pub fn face_minimums(&self) -> Option<&[f32]> {
        self.face_minimums.as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::SurfaceOptions;
    use crate::samples;

    /// The driver's frame is `frame_instances` of `lod::levels`, the two steps every host took.
    #[test]
    fn update_is_the_levels_then_the_instances() {
        let mesh = samples::icosphere(2);
        let surface = Surface::new(&mesh, &SurfaceOptions::new(crate::Scheme::Pn)).unwrap();
        let frame = surface.frame(&mesh).unwrap();
        for spacing in [Spacing::Grid, Spacing::FractionalOdd, Spacing::Equal] {
            let lod = Lod::Tolerance {
                max_deviation: 0.002,
            };
            let mut driver = InstancedDriver::new(spacing);
            let got = driver.update(&surface, &frame, &lod).unwrap().clone();
            let (edges, faces) =
                lod::levels(&mesh, surface.topology(), frame.nets(), &lod).unwrap();
            let table = PartTable::new(spacing);
            let t = surface.topology();
            let want = instanced::frame_instances(
                &table,
                t,
                surface.triangles(),
                &t.position_ids,
                &edges,
                faces.as_deref(),
            )
            .unwrap();
            assert_eq!(got.records, want.records, "{spacing:?}");
            assert_eq!(got.instances, want.instances);
            assert_eq!(got.draws, want.draws);
            assert_eq!(driver.edge_levels(), &edges[..]);
            assert_eq!(driver.face_minimums(), faces.as_deref());
        }
    }

    /// Wrong levels and a foreign frame are errors that keep the previous draws.
    #[test]
    fn an_error_keeps_the_previous_frame() {
        let mesh = samples::icosphere(1);
        let surface = Surface::new(&mesh, &SurfaceOptions::new(crate::Scheme::Pn)).unwrap();
        let other = Surface::new(&mesh, &SurfaceOptions::new(crate::Scheme::Pn)).unwrap();
        let mut driver = InstancedDriver::new(Spacing::Equal);
        let edges = vec![3.0; surface.topology().edges.len()];
        let before = driver.set_levels(&surface, &edges, None).unwrap().clone();
        assert!(driver.set_levels(&surface, &edges[1..], None).is_err());
        let foreign = other.frame(&mesh).unwrap();
        let lod = Lod::Tolerance {
            max_deviation: 0.01,
        };
        assert!(matches!(
            driver.update(&surface, &foreign, &lod),
            Err(RefineError::ForeignFrame)
        ));
        assert_eq!(driver.frame().records, before.records);
        assert_eq!(driver.frame().instances, before.instances);
        assert_eq!(driver.edge_levels(), &edges[..]);
    }
}
