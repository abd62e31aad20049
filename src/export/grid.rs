//! The export's grid of views: yaw steps of 360/N degrees from the options' yaw, pitch rows
//! centred on the options' pitch, so the first view is the camera `glview MODEL -o` uses.
use super::ExportOptions;
use crate::{Error, Result};

/// Steepest pitch a row may have: at ±90° the orbit camera's up vector is undefined.
const MAX_PITCH: f32 = 89.0;

/// Yaw and pitch of every view; view `v` is yaw `v % yaws.len()`, pitch `v / yaws.len()`.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Degrees in [0, 360), the options' yaw first.
    pub yaws: Vec<f32>,
    /// Degrees, lowest first.
    pub pitches: Vec<f32>,
    /// The row of the options' pitch (the first view is `start_pitch * yaws.len()`).
    pub start_pitch: usize,
}

impl Grid {
    /// The grid of `opts`, or a usage error naming the option that makes it impossible.
    pub fn of(opts: &ExportOptions) -> Result<Grid> {
        let (ny, np) = (opts.yaw_steps, opts.pitch_steps);
        if !(1..=360).contains(&ny) {
            return Err(Error::Usage("--yaw-steps must be 1 to 360".into()));
        }
        if !(1..=15).contains(&np) {
            return Err(Error::Usage("--pitch-steps must be 1 to 15".into()));
        }
        let step = opts.pitch_step;
        if !(step.is_finite() && step > 0.0 && step <= 90.0) {
            return Err(Error::Usage(
                "--pitch-step must be above 0 and at most 90".into(),
            ));
        }
        let (yaw0, pitch0) = (opts.options.camera.yaw, opts.options.camera.pitch);
        // Yaw 0 is exactly the options' (after reduction to [0, 360)): the first view is
        // drawn with the same number `glview -o` is given, not one recomputed from a sum.
        let yaws = (0..ny)
            .map(|i| (yaw0 + 360.0 * i as f32 / ny as f32).rem_euclid(360.0))
            .collect();
        let start_pitch = ((np - 1) / 2) as usize;
        let pitches: Vec<f32> = (0..np as usize)
            .map(|j| {
                if j == start_pitch {
                    pitch0
                } else {
                    pitch0 + (j as f32 - start_pitch as f32) * step
                }
            })
            .collect();
        if pitches.iter().any(|p| p.abs() > MAX_PITCH) {
            return Err(Error::Usage(format!(
                "--pitch-steps {np} x --pitch-step {step} from pitch {pitch0} reaches {:?}: \
                 rows must stay within ±{MAX_PITCH}°",
                pitches
            )));
        }
        Ok(Grid {
            yaws,
            pitches,
            start_pitch,
        })
    }

    /// Number of views.
    pub fn len(&self) -> usize {
        self.yaws.len() * self.pitches.len()
    }

    /// Whether the grid has no view (never, once made by [`Grid::of`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first view: the options' own camera.
    pub fn start(&self) -> usize {
        self.start_pitch * self.yaws.len()
    }

    /// (yaw, pitch) of view `v`.
    pub fn angles(&self, v: usize) -> (f32, f32) {
        let n = self.yaws.len();
        (self.yaws[v % n], self.pitches[v / n])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(yaw: f32, pitch: f32, ny: u32, np: u32) -> Result<Grid> {
        let mut o = ExportOptions::default();
        o.options.camera.yaw = yaw;
        o.options.camera.pitch = pitch;
        o.yaw_steps = ny;
        o.pitch_steps = np;
        Grid::of(&o)
    }

    #[test]
    fn first_view_is_the_options_camera_exactly() {
        for (yaw, pitch, ny, np) in [(30.0, 25.0, 36, 5), (12.3, -7.7, 4, 2), (359.9, 0.1, 7, 1)] {
            let g = grid(yaw, pitch, ny, np).unwrap();
            assert_eq!(g.angles(g.start()), (yaw, pitch));
            assert_eq!(g.len(), (ny * np) as usize);
            // Every other view is one yaw step of 360/N away from its neighbour.
            for i in 1..g.yaws.len() {
                let d = (g.yaws[i] - g.yaws[i - 1]).rem_euclid(360.0);
                assert!((d - 360.0 / ny as f32).abs() < 1e-3, "{d}");
            }
        }
    }

    #[test]
    fn impossible_grids_are_usage_errors() {
        assert!(grid(30.0, 25.0, 0, 5).is_err());
        assert!(grid(30.0, 25.0, 36, 16).is_err());
        // 25 + 4 rows of 15 above the middle one: 85 fits; 9 rows reach 85 + 15.
        assert!(grid(30.0, 25.0, 36, 9).is_ok());
        let e = grid(30.0, 25.0, 36, 11).unwrap_err().to_string();
        assert!(e.contains("within"), "{e}");
    }
}
