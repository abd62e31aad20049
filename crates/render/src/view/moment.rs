//! Which moment of the file's animations a picture shows (`--animation`, `--time`): resolved
//! against the loaded scene, so a name or index the file does not have is a one-line error
//! listing what it has, before anything is drawn. No GL.
use crate::error::{Error, Result};
use crate::options::Options;
use crate::scene::motion::{AnimationInfo, Moment};
use crate::scene::Scene;

/// The moment `args` asks of `scene`: None without `--time` (the static pose, every picture
/// as before), else `--animation` (by index, then by name; default the first) at `--time`.
/// `--animation` or `--time` on a scene without animations, or an animation it does not
/// have, is an [`Error::Usage`] naming the model and listing its animations.
pub fn moment(args: &Options, scene: &Scene) -> Result<Option<Moment>> {
    // `--keys` may hold the play keys (Space, `.`, `,`, `A`): the moment is the one they
    // lead to (the settled options have no keys left, so this recurses once).
    if args.camera.keys.is_some() {
        return moment(&crate::view::View::settled(args, scene)?, scene);
    }
    let m = &args.motion;
    if m.time.is_none() && m.animation.is_none() {
        return Ok(None);
    }
    let all = scene.animations();
    let asked = match (&m.animation, m.time) {
        (Some(a), _) => format!("--animation {a}"),
        (None, t) => format!("--time {}", t.unwrap_or_default()),
    };
    let animation = match find(all, m.animation.as_deref()) {
        Ok(a) => a,
        Err(Missing::None) => {
            return Err(Error::Usage(format!(
                "{asked}: {} has no animations",
                model_name(args, scene)
            )))
        }
        Err(Missing::NoSuch) => {
            return Err(Error::Usage(format!(
                "{asked}: {} has no such animation; it has {}",
                model_name(args, scene),
                listing(all)
            )))
        }
    };
    // `--animation` alone names what an animated output plays; a still stays static.
    Ok(m.time.map(|t| Moment {
        animation,
        seconds: f64::from(t),
    }))
}

/// Poses a scene loaded without a renderer (the reference renderer's, a comparison's or a
/// sheet's) at the moment `args` asks, as the session poses a renderer's, before anything
/// reads its bounds.
pub fn pose_scene(args: &Options, scene: &mut Scene) -> Result<()> {
    let at = moment(args, scene)?;
    if at.is_some() {
        scene.pose(at)?;
    }
    Ok(())
}

/// Why [`find`] found no animation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Missing {
    /// The file has no animations at all.
    None,
    /// It has some, but not the one asked for.
    NoSuch,
}

/// The animation `asked` names among `all` (`--animation`, and the play keys' and the
/// server's view of it): an index in range, else `all` (every animation together: the
/// merged entry, or the only animation), else an exact name of one of the file's; not
/// asked, the default ([`AnimationInfo::default`]). Each caller words the error for its
/// own place (an option, a key).
pub(crate) fn find(all: &[AnimationInfo], asked: Option<&str>) -> Result<usize, Missing> {
    if all.is_empty() {
        return Err(Missing::None);
    }
    let Some(asked) = asked else {
        return Ok(all.iter().position(|a| a.default).unwrap_or(0));
    };
    let asked = asked.trim();
    match asked.parse::<usize>() {
        Ok(i) if i < all.len() => Some(i),
        _ if asked == "all" => all.iter().position(|a| a.together).or(Some(0)),
        _ => all.iter().position(|a| a.name == asked && !a.together),
    }
    .ok_or(Missing::NoSuch)
}

/// `2 animations: 0 "Walk" (2.00 s), 1 (unnamed, 1.00 s)`.
fn listing(all: &[AnimationInfo]) -> String {
    let each: Vec<String> = all
        .iter()
        .enumerate()
        .map(|(i, a)| {
            if a.together {
                format!(
                    "{i} \"all\" (every animation together, {:.2} s)",
                    a.duration
                )
            } else if a.name.is_empty() {
                format!("{i} (unnamed, {:.2} s)", a.duration)
            } else {
                format!("{i} {:?} ({:.2} s)", a.name, a.duration)
            }
        })
        .collect();
    let n = all.len();
    let s = if n == 1 { "" } else { "s" };
    format!("{n} animation{s}: {}", each.join(", "))
}

/// The model's file as the user named it, else the scene's name (the built-in scene, a
/// caller's arrays).
fn model_name(args: &Options, scene: &Scene) -> String {
    args.load
        .model
        .as_ref()
        .map_or_else(|| scene.name.clone(), |p| p.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn infos(names: &[&str]) -> Vec<AnimationInfo> {
        names
            .iter()
            .map(|n| AnimationInfo {
                name: (*n).into(),
                duration: 1.5,
                channels: 2,
                together: false,
                default: false,
            })
            .collect()
    }

    #[test]
    fn an_index_in_range_wins_then_an_exact_name() {
        let all = infos(&["Walk", "1", "Run"]);
        assert_eq!(find(&all, Some("2")), Ok(2));
        assert_eq!(find(&all, Some("Run")), Ok(2));
        assert_eq!(find(&all, Some("run")), Err(Missing::NoSuch));
        assert_eq!(find(&all, Some("3")), Err(Missing::NoSuch));
        assert_eq!(find(&all, Some("1")), Ok(1));
        assert_eq!(find(&all, None), Ok(0));
        assert_eq!(find(&[], None), Err(Missing::None));
        assert_eq!(find(&[], Some("0")), Err(Missing::None));
        // `all`: the merged entry (the only animation where there is one); not asked, the
        // default the loader marked.
        assert_eq!(find(&all, Some("all")), Ok(0));
        let mut merged = infos(&["Walk", "Run", "all"]);
        merged[2].together = true;
        merged[2].default = true;
        assert_eq!(find(&merged, Some("all")), Ok(2));
        assert_eq!(find(&merged, None), Ok(2));
        merged[0].name = "all".into();
        assert_eq!(find(&merged, Some("all")), Ok(2), "the keyword wins");
    }

    #[test]
    fn the_listing_names_every_animation_by_index_and_name() {
        let all = infos(&["Walk", ""]);
        assert_eq!(
            listing(&all),
            "2 animations: 0 \"Walk\" (1.50 s), 1 (unnamed, 1.50 s)"
        );
    }

    #[test]
    fn without_time_or_animation_the_static_pose() -> Result<()> {
        let scene = Scene::from_meshes("s", Vec::new(), Vec::new());
        assert_eq!(moment(&Options::default(), &scene)?, None);
        Ok(())
    }

    #[test]
    fn time_or_animation_on_a_still_model_says_it_has_none() {
        let scene = Scene::from_meshes("still", Vec::new(), Vec::new());
        let mut o = Options::default();
        o.motion.time = Some(0.5);
        let e = moment(&o, &scene).expect_err("no animations");
        assert_eq!(
            e.to_string(),
            "invalid option: --time 0.5: still has no animations"
        );
        o.motion.time = None;
        o.motion.animation = Some("Walk".into());
        let e = moment(&o, &scene).expect_err("no animations");
        assert!(e
            .to_string()
            .contains("--animation Walk: still has no animations"));
    }
}
