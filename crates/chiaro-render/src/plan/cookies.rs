//! Where each light's cookie lives on the GPU: directional and spot cookies are layers of
//! one 2D array, point cookies cubes of one cube array, numbered in scene order. A pure
//! function of the scene, so the GPU scene (which uploads them) and the frame (which
//! points lights at them) agree.

use chiaro_scene::{LightKind, Scene};

/// The array a cookie is a layer of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CookieArray {
    /// Directional and spot cookies.
    Flat,
    /// Point cookies, six faces each.
    Cube,
}

/// Per scene light, its cookie's array and layer (a cube index for the cube array).
pub fn cookie_slots(scene: &Scene) -> Vec<Option<(CookieArray, u32)>> {
    let (mut flat, mut cube) = (0, 0);
    scene
        .lights
        .iter()
        .map(|light| {
            light.cookie?;
            Some(match light.kind {
                LightKind::Point => {
                    cube += 1;
                    (CookieArray::Cube, cube - 1)
                }
                _ => {
                    flat += 1;
                    (CookieArray::Flat, flat - 1)
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{Cookie, Light};
    use glam::{Vec2, Vec3};

    #[test]
    fn cookies_are_numbered_per_array_in_scene_order() {
        let cookie = Some(Cookie { image: 0, size_m: Vec2::ONE });
        let with = |kind, cookie| Light { cookie, ..Light::new(kind, Vec3::ZERO, Vec3::NEG_Y) };
        let spot = LightKind::Spot { inner_cone_rad: 0.3, outer_cone_rad: 0.5 };
        let scene = Scene {
            lights: vec![
                with(LightKind::Point, cookie),
                with(LightKind::Directional, cookie),
                with(spot, None),
                with(spot, cookie),
                with(LightKind::Point, cookie),
            ],
            ..Scene::default()
        };
        assert_eq!(
            cookie_slots(&scene),
            vec![
                Some((CookieArray::Cube, 0)),
                Some((CookieArray::Flat, 0)),
                None,
                Some((CookieArray::Flat, 1)),
                Some((CookieArray::Cube, 1)),
            ]
        );
    }
}
