//! Orbit, pan and zoom of a look-at camera, as in ParaView and Blender:
//! orbiting turns `from` about `to` (yaw about the camera's up axis, pitch
//! about its right axis, never across the poles), panning moves both along
//! the image plane in proportion to the distance, zooming scales the
//! distance.

use fogbank::desc::CameraDesc;
use glam::{Quat, Vec3};

/// Pitch stays this far (radians) from straight up or down, where the
/// look-at frame degenerates.
const POLE_MARGIN: f32 = 0.02;

fn frame(c: &CameraDesc) -> (Vec3, Vec3, Vec3, f32) {
    let (from, to) = (Vec3::from(c.from), Vec3::from(c.to));
    let up = Vec3::from(c.up).try_normalize().unwrap_or(Vec3::Y);
    let offset = from - to;
    let dist = offset.length().max(1e-6);
    let forward = -offset / dist;
    let right = forward.cross(up).try_normalize().unwrap_or(Vec3::X);
    (up, right, offset, dist)
}

/// Turns the camera about its target by `yaw` and `pitch` degrees: positive
/// yaw moves it to its left (the volume turns right, as when dragging to
/// the right in Blender or ParaView), positive pitch moves it up.
pub fn orbit(c: &mut CameraDesc, yaw_deg: f32, pitch_deg: f32) {
    let (up, right, offset, dist) = frame(c);
    let yawed = Quat::from_axis_angle(up, -yaw_deg.to_radians()) * offset;
    // Limit pitch so the view direction never reaches ±up.
    let elevation = (yawed.dot(up) / dist).clamp(-1.0, 1.0).asin();
    let max = std::f32::consts::FRAC_PI_2 - POLE_MARGIN;
    let target = (elevation + pitch_deg.to_radians()).clamp(-max, max);
    let right = (-yawed).cross(up).try_normalize().unwrap_or(right);
    let pitched = Quat::from_axis_angle(right, elevation - target) * yawed;
    c.from = (Vec3::from(c.to) + pitched).to_array();
}

/// Moves camera and target along the image plane by `dx`, `dy` in units of
/// the image height at the target's distance.
pub fn pan(c: &mut CameraDesc, dx: f32, dy: f32) {
    let (_, right, offset, dist) = frame(c);
    let cam_up = right.cross(-offset / dist);
    let half_height = dist * (0.5 * c.fov.to_radians()).tan();
    let shift = (-dx * right + dy * cam_up) * 2.0 * half_height;
    c.from = (Vec3::from(c.from) + shift).to_array();
    c.to = (Vec3::from(c.to) + shift).to_array();
}

/// Scales the distance to the target by `factor` (< 1 moves closer).
pub fn zoom(c: &mut CameraDesc, factor: f32) {
    let to = Vec3::from(c.to);
    let offset = Vec3::from(c.from) - to;
    c.from = (to + offset * factor.clamp(0.05, 20.0)).to_array();
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> CameraDesc {
        CameraDesc {
            from: [0.0, 0.0, 2.0],
            ..Default::default()
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_a_full_turn_returns() {
        let mut c = cam();
        for _ in 0..12 {
            orbit(&mut c, 30.0, 0.0);
            assert!((Vec3::from(c.from).length() - 2.0).abs() < 1e-4);
        }
        assert!(Vec3::from(c.from).distance(Vec3::new(0.0, 0.0, 2.0)) < 1e-3);
        orbit(&mut c, 90.0, 0.0);
        assert!(
            Vec3::from(c.from).distance(Vec3::new(-2.0, 0.0, 0.0)) < 1e-3,
            "{:?}",
            c.from
        );
    }

    #[test]
    fn pitch_stops_short_of_the_pole() {
        let mut c = cam();
        orbit(&mut c, 0.0, 200.0);
        let from = Vec3::from(c.from);
        assert!(
            from.y > 1.99 && from.y < 2.0 && from.length() > 1.999,
            "{from:?}"
        );
    }

    #[test]
    fn pan_moves_both_and_zoom_scales_the_distance() {
        let mut c = cam();
        pan(&mut c, 0.5, 0.0);
        assert!(c.from[0] < 0.0 && (c.from[0] - c.to[0]).abs() < 1e-6);
        zoom(&mut c, 0.5);
        assert!((Vec3::from(c.from).distance(Vec3::from(c.to)) - 1.0).abs() < 1e-5);
    }
}
