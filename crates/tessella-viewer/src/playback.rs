//! A loaded file's animation clips played in the viewer: the poser, the clock of the clip
//! playing, and the pose buffers every frame reuses (`tessella_core::animation::Poser`).

use crate::error::ViewerError;
use tessella_core::animation::{AnimatedMesh, Poser};
use tessella_core::Mesh;

/// The sample the viewer offers beside the core's static ones: the animated creature
/// (`tessella_core::samples::animated_creature`, the mesh `samples/animated-creature.glb` holds).
pub const ANIMATED_SAMPLE: &str = "animated-creature";
/// Its icosphere subdivisions (as `tessella samples` writes it).
const ANIMATED_SAMPLE_SUBDIVISIONS: u32 = 2;

/// The time of a clip `duration` seconds long that started at `from` seconds and has played
/// `elapsed` seconds since: looping, so always within `[0, duration]` (a clip of no duration
/// stays at 0).
pub fn looped(from: f32, elapsed: f64, duration: f32) -> f32 {
    if duration.is_nan() || duration <= 0.0 {
        return 0.0;
    }
    let t = (f64::from(from) + elapsed.max(0.0)).rem_euclid(f64::from(duration));
    t as f32
}

/// An animated mesh with clips, ready to pose frames.
pub struct Playback {
    poser: Poser,
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    /// When the clip started playing: (page clock in ms, clip time in seconds then).
    started: Option<(f64, f32)>,
}

impl std::fmt::Debug for Playback {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Playback")
            .field("clips", &self.poser.clip_count())
            .field("vertices", &self.poser.vertex_count())
            .finish()
    }
}

impl Playback {
    /// `model`'s animation, checked; `None` when it has no clips (nothing to play).
    pub fn new(name: &str, model: AnimatedMesh) -> Result<Option<Playback>, ViewerError> {
        if model.clips.is_empty() {
            return Ok(None);
        }
        let poser = Poser::new(model)
            .map_err(|e| ViewerError::Refused(format!("cannot animate {name}: {e}")))?;
        let n = poser.vertex_count();
        Ok(Some(Playback {
            positions: vec![[0.0; 3]; n],
            normals: poser.has_normals().then(|| vec![[0.0; 3]; n]),
            poser,
            started: None,
        }))
    }

    /// The bundled animated sample.
    pub fn sample() -> Result<Playback, ViewerError> {
        let model = tessella_core::samples::animated_creature(ANIMATED_SAMPLE_SUBDIVISIONS);
        Playback::new(ANIMATED_SAMPLE, model)?
            .ok_or_else(|| ViewerError::Refused("the animated sample has no clips".into()))
    }

    /// The rest pose (the nodes' own transforms, in the scene's space): what the camera
    /// frames and what the panels are built on.
    pub fn rest(&self) -> Result<Mesh, ViewerError> {
        self.poser
            .mesh(None, 0.0)
            .map_err(|e| ViewerError::Refused(format!("cannot pose the rest pose: {e}")))
    }

    pub fn vertex_count(&self) -> usize {
        self.poser.vertex_count()
    }

    /// The clips' names, in the file's order.
    pub fn clip_names(&self) -> Vec<String> {
        self.poser.clip_names().map(str::to_string).collect()
    }

    /// The clip a `clip` parameter names (by name, or by index), as an error naming the
    /// parameter otherwise.
    pub fn resolve(&self, clip: &str) -> Result<usize, ViewerError> {
        self.poser.clip_index(clip).map_err(|e| ViewerError::Param {
            name: "clip",
            message: e.to_string(),
        })
    }

    /// A clip's duration in seconds.
    pub fn duration(&self, clip: usize) -> f32 {
        self.poser.duration(clip).unwrap_or(0.0)
    }

    /// Restarts the clock: the next [`Playback::time_at`] while playing counts from the time
    /// it is given then.
    pub fn restart(&mut self) {
        self.started = None;
    }

    /// The clip time to show at page time `now_ms`: while `playing`, `time` when the clock
    /// (re)started, plus the time since, looping over the clip; paused, `time`.
    pub fn time_at(&mut self, clip: usize, time: f32, playing: bool, now_ms: f64) -> f32 {
        let duration = self.duration(clip);
        if !playing {
            self.started = None;
            return time;
        }
        let (from_ms, from) = *self.started.get_or_insert((now_ms, time));
        looped(from, (now_ms - from_ms) / 1000.0, duration)
    }

    /// Poses `clip` at `time` into the reused buffers: positions, and normals when the file
    /// has them (else the panels compute them).
    #[allow(clippy::type_complexity)]
    pub fn pose(
        &mut self,
        clip: usize,
        time: f32,
    ) -> Result<(&[[f32; 3]], Option<&[[f32; 3]]>), ViewerError> {
        self.poser
            .pose_into(
                Some(clip),
                time,
                &mut self.positions,
                self.normals.as_deref_mut(),
            )
            .map_err(|e| ViewerError::Refused(format!("cannot pose clip {clip}: {e}")))?;
        Ok((&self.positions, self.normals.as_deref()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_loops_over_the_clip() {
        assert_eq!(looped(0.0, 0.5, 2.0), 0.5);
        assert_eq!(looped(1.5, 1.0, 2.0), 0.5);
        assert_eq!(looped(0.25, 4.0, 2.0), 0.25);
        assert_eq!(looped(0.7, 3.0, 0.0), 0.0);
        assert!(looped(0.0, 1e9, 1.3) < 1.3);
    }

    #[test]
    fn paused_shows_the_time_given_and_playing_counts_from_it() {
        let mut playback = Playback::sample().unwrap();
        let wave = playback.resolve("wave").unwrap();
        let duration = playback.duration(wave);
        assert!(duration > 0.5);
        assert_eq!(playback.time_at(wave, 0.5, false, 1000.0), 0.5);
        // Playing from 0.5 at page time 2000 ms: 250 ms later it is at 0.75.
        assert_eq!(playback.time_at(wave, 0.5, true, 2000.0), 0.5);
        assert!((playback.time_at(wave, 0.5, true, 2250.0) - 0.75).abs() < 1e-6);
        playback.restart();
        assert_eq!(playback.time_at(wave, 0.1, true, 5000.0), 0.1);
        assert!(matches!(
            playback.resolve("dance"),
            Err(ViewerError::Param { name: "clip", .. })
        ));
        assert_eq!(playback.resolve("1").unwrap(), 1);
    }
}
