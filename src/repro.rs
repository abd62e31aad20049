//! The command line that reproduces a picture, for its PNG text: the words the user gave
//! (every option that changes pixels, as typed) without the ones that say where and how
//! often to write, with the camera, size and state keys of the moment in place of the ones
//! given (a window's view has moved since start-up).
use crate::cli::Args;
use crate::options::Options;
use clap::CommandFactory;

/// Options that do not change the picture, or that the moment's state replaces.
const DROPPED: &[&str] = &[
    "output",
    "stats",
    "frames",
    "screenshot-dir",
    "keys",
    "size",
    "yaw",
    "pitch",
    "distance",
    "target",
    "fov",
    "ortho",
    "near",
];

/// How many values the option `word` (`--name`, `--name=value` or `-x`) takes from the
/// following words, and whether it is dropped. None: not an option (a model path, a value).
fn option(cmd: &clap::Command, word: &str) -> Option<(usize, bool)> {
    let (arg, inline) = if let Some(long) = word.strip_prefix("--") {
        let (name, value) = long
            .split_once('=')
            .map_or((long, false), |(n, _)| (n, true));
        (
            cmd.get_arguments().find(|a| a.get_long() == Some(name))?,
            value,
        )
    } else {
        let mut chars = word.strip_prefix('-')?.chars();
        let short = chars.next()?;
        let inline = chars.next().is_some();
        (
            cmd.get_arguments().find(|a| a.get_short() == Some(short))?,
            inline,
        )
    };
    let takes = arg.get_action().takes_values() && !inline;
    let dropped = arg.get_long().is_some_and(|l| DROPPED.contains(&l));
    Some((usize::from(takes), dropped))
}

/// `args.words` without the dropped options and their values.
fn kept_words(args: &Options) -> Vec<String> {
    thread_local! {
        // Built once per thread: building it cost more than the rest of a kept render's
        // set-up.
        static CMD: clap::Command = Args::command();
    }
    CMD.with(|cmd| kept_words_with(cmd, args))
}

fn kept_words_with(cmd: &clap::Command, args: &Options) -> Vec<String> {
    let mut out = Vec::new();
    let mut words = args.words.iter().peekable();
    while let Some(w) = words.next() {
        let Some((takes, dropped)) = option(cmd, w) else {
            out.push(w.clone());
            continue;
        };
        let mut value = None;
        if takes == 1 {
            // `--ortho` takes its value only when one follows.
            let optional = w == "--ortho";
            if !optional || words.peek().is_some_and(|v| v.parse::<f32>().is_ok()) {
                value = words.next();
            }
        }
        if !dropped {
            out.push(w.clone());
            out.extend(value.cloned());
        }
    }
    out
}

/// What decides the scene, the environment and the lights of a picture: the words but for
/// camera, size, keys and output, and the model file's size and time (so a file changed
/// between two pictures is read again). Equal keys may share a renderer.
pub fn scene_key(args: &Options) -> String {
    let stamp = args
        .model
        .as_ref()
        .and_then(|m| std::fs::metadata(m).ok())
        .map(|m| format!("{} {:?}", m.len(), m.modified().ok()))
        .unwrap_or_default();
    let mut key = kept_words(args).join("\0");
    key.push('\0');
    key.push_str(&stamp);
    key
}

/// `glview WORDS... --size WxH --keys "..." CAMERA`: `camera` is the camera as options
/// (`--yaw ... --pitch ...`), `keys` the state-changing keys pressed (camera keys excluded:
/// the camera options already hold their effect).
pub fn command_line(args: &Options, size: (u32, u32), keys: &[String], camera: &str) -> String {
    let mut words = vec!["glview".to_string()];
    words.extend(kept_words(args));
    words.push("--size".into());
    words.push(format!("{}x{}", size.0, size.1));
    if !keys.is_empty() {
        words.push("--keys".into());
        words.push(keys.join(" "));
    }
    let quoted: Vec<String> = words
        .iter()
        .map(|w| {
            shlex::try_quote(w)
                .map(|q| q.into_owned())
                .unwrap_or_else(|_| w.clone())
        })
        .collect();
    format!("{} {camera}", quoted.join(" "))
}

/// The keys of `--keys` that change state rather than the camera, in order.
pub fn state_keys(keys: Option<&str>) -> Vec<String> {
    keys.unwrap_or_default()
        .split_whitespace()
        .filter(|k| crate::keys::action_for(k).is_some_and(|a| a.changes_state()))
        .map(String::from)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(words: &[&str]) -> Args {
        Args::from_words(words.iter().map(|w| w.to_string())).unwrap()
    }

    #[test]
    fn drops_output_camera_and_counts_and_keeps_the_rest() {
        let a = args(&[
            "my model.obj",
            "-o",
            "out.png",
            "--yaw=10",
            "--ortho",
            "--light",
            "dir:0,-1,0",
            "--stats",
            "--shadow-bias",
            "0.001",
            "--fov",
            "50",
            "--keys",
            "Left S",
        ]);
        assert_eq!(
            kept_words(&a),
            [
                "my model.obj",
                "--light",
                "dir:0,-1,0",
                "--shadow-bias",
                "0.001"
            ]
        );
        let line = command_line(&a, (64, 48), &state_keys(a.keys.as_deref()), "--yaw 1");
        assert_eq!(
            line,
            "glview 'my model.obj' --light 'dir:0,-1,0' --shadow-bias 0.001 --size 64x48 \
             --keys S --yaw 1"
        );
    }
}
