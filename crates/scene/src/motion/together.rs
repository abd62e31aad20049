//! Every animation of a file on one clock (`--animation all`), and which one plays where
//! none is named. A face capture split into head, eyes, mouth and brows, Blender's NLA
//! strips of different objects and Khronos' InterpolationTest drive different nodes in each
//! animation and are meant to play together; a Mixamo bundle's walk and run drive the same
//! skeleton and are meant to play one at a time. The merged animation is the file's
//! animations' channels in file order, each sampled at the same moment (each holds its
//! last key after its own end), so it lasts as long as the longest and is the picture of a
//! file whose animations were merged into one by hand; where two drive the same node's
//! property, the later one's channel is applied last and wins.
//!
//! The default, as the glTF Sample Viewer's page chooses (it starts every animation that
//! shares no target with one already started): every animation together where no two
//! share a target (node and property, or material factor), else the first. Where only some
//! overlap the Sample Viewer plays a subset; glview plays the first (docs/gltf/motion.md).
use crate::motion::channels::Animation;
use crate::motion::AnimationInfo;

/// What an animation's channel sets: a node's translation, rotation, scale or weights, or
/// a material's factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Target {
    Node(usize, u8),
    Material(usize, u8),
}

fn targets(a: &Animation) -> Vec<Target> {
    let mut t: Vec<Target> = a
        .channels
        .iter()
        .map(|c| Target::Node(c.node, c.path as u8))
        .chain(
            a.materials
                .iter()
                .map(|m| Target::Material(m.material, m.property as u8)),
        )
        .collect();
    t.sort_unstable();
    t.dedup();
    t
}

fn shared(a: &[Target], b: &[Target]) -> usize {
    a.iter().filter(|t| b.binary_search(t).is_ok()).count()
}

/// The animations followed by their merge where there are two or more, the default one
/// marked ([`AnimationInfo::default`]).
pub(crate) fn with_merged(mut animations: Vec<Animation>) -> Vec<Animation> {
    if animations.len() < 2 {
        if let Some(a) = animations.first_mut() {
            a.info.default = true;
        }
        return animations;
    }
    let each: Vec<Vec<Target>> = animations.iter().map(targets).collect();
    let disjoint = (0..each.len()).all(|i| (0..i).all(|k| shared(&each[i], &each[k]) == 0));
    let merged = Animation {
        info: AnimationInfo {
            name: "all".into(),
            duration: animations
                .iter()
                .map(|a| a.info.duration)
                .fold(0.0, f64::max),
            channels: animations.iter().map(|a| a.info.channels).sum(),
            together: true,
            default: disjoint,
        },
        channels: animations.iter().flat_map(|a| a.channels.clone()).collect(),
        materials: animations
            .iter()
            .flat_map(|a| a.materials.clone())
            .collect(),
    };
    animations[0].info.default = !disjoint;
    animations.push(merged);
    animations
}

/// `--check`'s lines: the nodes each of the file's animations drives (`names`: the file's
/// node names), a warning for each pair that drives the same ones, and the default.
pub(crate) fn check_lines(animations: &[Animation], names: &[Option<String>]) -> Vec<String> {
    let file: Vec<&Animation> = animations.iter().filter(|a| !a.info.together).collect();
    if file.len() < 2 {
        return Vec::new();
    }
    let node = |n: usize| match names.get(n).and_then(Option::as_deref) {
        Some(name) => format!("{n} {name:?}"),
        None => n.to_string(),
    };
    let label = |i: usize| format!("{i} {:?}", file[i].info.name);
    let mut out = Vec::new();
    let nodes: Vec<Vec<usize>> = file
        .iter()
        .map(|a| {
            let mut n: Vec<usize> = a.channels.iter().map(|c| c.node).collect();
            n.sort_unstable();
            n.dedup();
            n
        })
        .collect();
    for (i, n) in nodes.iter().enumerate() {
        let shown: Vec<String> = n.iter().take(6).map(|&k| node(k)).collect();
        let more = n.len().saturating_sub(6);
        let more = if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        };
        out.push(format!(
            "animation {}: drives {} node{}: {}{more}",
            label(i),
            n.len(),
            if n.len() == 1 { "" } else { "s" },
            shown.join(", ")
        ));
    }
    let each: Vec<Vec<Target>> = file.iter().map(|a| targets(a)).collect();
    // (earlier, later, nodes both drive) of every pair that shares a target.
    let mut pairs: Vec<(usize, usize, Vec<usize>)> = Vec::new();
    for i in 0..file.len() {
        for k in 0..i {
            let same: Vec<usize> = nodes[i]
                .iter()
                .copied()
                .filter(|n| nodes[k].binary_search(n).is_ok())
                .collect();
            if !same.is_empty() || shared(&each[i], &each[k]) > 0 {
                pairs.push((k, i, same));
            }
        }
    }
    let what = |(k, i, same): &(usize, usize, Vec<usize>)| {
        let first = same
            .first()
            .map_or_else(|| "a material".into(), |&n| format!("node {}", node(n)));
        format!(
            "{} and {} drive {} of the same nodes (first: {first})",
            label(*k),
            label(*i),
            same.len()
        )
    };
    let later = "played together (--animation all), the later one's channels win there";
    // A bundle of clips on one skeleton shares nodes in every pair: one line, not dozens.
    if pairs.len() > 3 {
        out.push(format!(
            "warning: {} pairs of the {} animations drive the same nodes, first animations {}; \
             {later}",
            pairs.len(),
            file.len(),
            what(&pairs[0])
        ));
    } else {
        for p in &pairs {
            out.push(format!("warning: animations {}; {later}", what(p)));
        }
    }
    let default = animations.iter().position(|a| a.info.default).unwrap_or(0);
    out.push(if animations[default].info.together {
        format!(
            "default animation: all {} together (they drive different nodes, as the glTF \
             Sample Viewer plays them)",
            file.len()
        )
    } else {
        "default animation: 0 (the animations drive the same nodes: --animation all plays \
         them together)"
            .into()
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::channels::Channel;
    use crate::motion::sample::{Interp, Keys};
    use crate::motion::Path;

    fn animation(name: &str, nodes: &[usize], end: f32) -> Animation {
        let keys = std::sync::Arc::new(Keys {
            times: vec![0.0, end],
            values: vec![0.0; 6],
            width: 3,
            interp: Interp::Linear,
            rotation: false,
        });
        Animation {
            info: AnimationInfo {
                name: name.into(),
                duration: f64::from(end),
                channels: nodes.len(),
                together: false,
                default: false,
            },
            channels: nodes
                .iter()
                .map(|&node| Channel {
                    node,
                    path: Path::Translation,
                    keys: keys.clone(),
                })
                .collect(),
            materials: Vec::new(),
        }
    }

    #[test]
    fn disjoint_animations_play_together_by_default_and_overlapping_ones_the_first() {
        let face = with_merged(vec![
            animation("head", &[1], 2.0),
            animation("eyes", &[2, 3], 3.0),
            animation("mouth", &[4], 1.0),
        ]);
        assert_eq!(face.len(), 4);
        let all = &face[3];
        assert!(all.info.together && all.info.default);
        assert_eq!((all.info.duration, all.channels.len()), (3.0, 4));
        assert!(face[..3].iter().all(|a| !a.info.default));
        let lines = check_lines(&face, &[None, None, Some("eyeL".into())]);
        assert!(
            lines[1].contains("drives 2 nodes: 2 \"eyeL\", 3"),
            "{lines:?}"
        );
        assert!(lines.last().unwrap().contains("all 3 together"));
        let bundle = with_merged(vec![
            animation("walk", &[1, 2], 1.0),
            animation("run", &[2, 5], 1.0),
        ]);
        assert!(bundle[0].info.default && !bundle[2].info.default);
        let lines = check_lines(&bundle, &[]);
        assert!(lines.iter().any(|l| l.starts_with("warning: animations 0 \"walk\" and 1 \"run\" drive 1 of the same nodes (first: node 2)")), "{lines:?}");
        let one = with_merged(vec![animation("walk", &[1], 1.0)]);
        assert_eq!(one.len(), 1);
        assert!(one[0].info.default);
    }
}
