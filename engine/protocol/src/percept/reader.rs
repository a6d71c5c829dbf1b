//! Reading a percept in one pass over its tokens ([`Cursor`]): each item reader is entered
//! after its list's head and leaves through the list's end, whatever it found inside.

use super::{
    FootContact, GameStatePercept, Heard, HeardFrom, JointReading, Percept, Polar, Seen, SeenLine,
    SeenPlayer, Vision, MAX_HEARD,
};
use crate::cursor::{Cursor, Token};
use crate::sexp::{parse_finite, SexpError};
use arrayvec::ArrayVec;
use libero_model::ServerKind;

/// The next child of the list the cursor is in.
enum Child<'a> {
    /// A sub-list was entered and this is its head; the reader must leave it.
    List(&'a str),
    Atom(&'a str),
    /// The list ended (its `)` read).
    End,
}

fn child<'a>(c: &mut Cursor<'a>) -> Result<Child<'a>, SexpError> {
    loop {
        match c.next_token() {
            Token::Close => return Ok(Child::End),
            Token::Atom(atom) => return Ok(Child::Atom(atom)),
            // An empty list or one without a head atom has been left by `head`.
            Token::Open => {
                if let Some(head) = c.head()? {
                    return Ok(Child::List(head));
                }
            }
            Token::End => return Err(SexpError::Unclosed(0)),
        }
    }
}

/// Read every item of `text` into `p`.
pub(super) fn read_items<'a>(
    text: &'a str,
    server: ServerKind,
    p: &mut Percept<'a>,
) -> Result<(), SexpError> {
    let mut c = Cursor::new(text);
    loop {
        let at = c.offset();
        match c.next_token() {
            Token::End => return Ok(()),
            Token::Close => return Err(SexpError::UnexpectedClose(at)),
            Token::Atom(atom) => {
                let _ = p.skipped.try_push(atom);
            }
            Token::Open => {
                let read = match c.head() {
                    Ok(Some(name)) => read_item(&mut c, name, server, p).map(|ok| (name, ok)),
                    Ok(None) => Ok(("", false)),
                    Err(e) => Err(e),
                };
                match read {
                    Ok((_, true)) => {}
                    Ok((name, false)) => {
                        let _ = p.skipped.try_push(name);
                    }
                    // Reported at the item's opening, wherever inside it the text ended.
                    Err(SexpError::Unclosed(_)) => return Err(SexpError::Unclosed(at)),
                    Err(e) => return Err(e),
                }
            }
        }
    }
}

/// One top-level item named `name`: whether it was read whole.
fn read_item<'a>(
    c: &mut Cursor<'a>,
    name: &'a str,
    server: ServerKind,
    p: &mut Percept<'a>,
) -> Result<bool, SexpError> {
    match name {
        "time" => Ok(named_numbers::<1>(c, "now")?
            .map(|[t]| p.time = Some(t))
            .is_some()),
        "GS" => read_game_state(c, &mut p.game).map(|()| true),
        "quat" => Ok(named_numbers::<4>(c, "q")?
            .map(|q| p.truth_orientation = Some(q))
            .is_some()),
        "pos" => Ok(named_numbers::<3>(c, "p")?
            .map(|v| p.truth_position = Some(v))
            .is_some()),
        "GYR" => Ok(named_numbers::<3>(c, "rt")?
            .map(|v| p.gyro = Some(to_robot_frame(v, server)))
            .is_some()),
        "ACC" => Ok(named_numbers::<3>(c, "a")?
            .map(|v| p.accel = Some(to_robot_frame(v, server)))
            .is_some()),
        "HJ" => Ok(read_joint(c)?.is_some_and(|j| p.joints.try_push(j).is_ok())),
        "FRP" => Ok(read_foot(c, server)?.is_some_and(|f| p.foot_contacts.try_push(f).is_ok())),
        "See" => {
            // Filled where it lies: a vision frame is kilobytes on the stack.
            let vision = p.vision.insert(Vision::default());
            read_vision(c, vision)?;
            Ok(!vision.overflowed)
        }
        "MIC" => read_mic(c, &mut p.heard),
        "hear" => Ok(read_hear(c)?.is_some_and(|h| p.heard.try_push(h).is_ok())),
        _ => c.leave().map(|()| false),
    }
}

/// SimSpark's body sensors use x right, y forward; ours are x forward, y left.
pub(super) fn to_robot_frame(v: [f64; 3], server: ServerKind) -> [f64; 3] {
    match server {
        ServerKind::RcssMj => v,
        ServerKind::SimSpark => [v[1], -v[0], v[2]],
    }
}

/// The `N` numbers of the first child list named `name`, the rest of the list read past.
fn named_numbers<const N: usize>(
    c: &mut Cursor<'_>,
    name: &str,
) -> Result<Option<[f64; N]>, SexpError> {
    let mut found = None;
    loop {
        match child(c)? {
            Child::List(head) if head == name && found.is_none() => found = c.numbers::<N>()?,
            Child::List(_) => c.leave()?,
            Child::Atom(_) => {}
            Child::End => return Ok(found),
        }
    }
}

fn read_game_state<'a>(c: &mut Cursor<'a>, gs: &mut GameStatePercept<'a>) -> Result<(), SexpError> {
    loop {
        let name = match child(c)? {
            Child::List(name) => name,
            Child::Atom(_) => continue,
            Child::End => return Ok(()),
        };
        let Some(value) = c.value()? else { continue };
        match name {
            "t" => gs.play_time = parse_finite(value),
            "pm" => gs.play_mode = Some(value),
            "tl" => gs.team_left = Some(value),
            "tr" => gs.team_right = Some(value),
            "sl" => gs.score_left = value.parse().ok(),
            "sr" => gs.score_right = value.parse().ok(),
            "unum" => gs.unum = value.parse().ok(),
            "team" => gs.side = Some(value),
            _ => {}
        }
    }
}

fn read_joint<'a>(c: &mut Cursor<'a>) -> Result<Option<JointReading<'a>>, SexpError> {
    let (mut perceptor, mut angle, mut velocity) = (None, None, None);
    loop {
        match child(c)? {
            Child::List("n") => perceptor = c.value()?,
            Child::List("ax") => angle = c.numbers::<1>()?.map(|[v]| v),
            Child::List("vx") => velocity = c.numbers::<1>()?.map(|[v]| v),
            Child::List(_) => c.leave()?,
            Child::Atom(_) => {}
            Child::End => break,
        }
    }
    Ok(perceptor
        .zip(angle)
        .map(|(perceptor, angle_deg)| JointReading {
            perceptor,
            angle_deg,
            velocity_deg: velocity,
        }))
}

fn read_foot<'a>(
    c: &mut Cursor<'a>,
    server: ServerKind,
) -> Result<Option<FootContact<'a>>, SexpError> {
    let (mut name, mut point, mut force) = (None, None, None);
    loop {
        match child(c)? {
            Child::List("n") => name = c.value()?,
            Child::List("c") => point = c.numbers::<3>()?,
            Child::List("f") => force = c.numbers::<3>()?,
            Child::List(_) => c.leave()?,
            Child::Atom(_) => {}
            Child::End => break,
        }
    }
    Ok(match (name, point, force) {
        (Some(name), Some(point), Some(force)) => Some(FootContact {
            name,
            point: to_robot_frame(point, server),
            force: to_robot_frame(force, server),
        }),
        _ => None,
    })
}

fn polar([distance, azimuth_deg, elevation_deg]: [f64; 3]) -> Polar {
    Polar {
        distance,
        azimuth_deg,
        elevation_deg,
    }
}

/// The first `(pol d a e)` of the list the cursor is in, the rest read past.
fn first_polar(c: &mut Cursor<'_>) -> Result<Option<Polar>, SexpError> {
    Ok(named_numbers::<3>(c, "pol")?.map(polar))
}

fn read_vision<'a>(c: &mut Cursor<'a>, vision: &mut Vision<'a>) -> Result<(), SexpError> {
    loop {
        match child(c)? {
            Child::List("P") => {
                if let Some(player) = read_player(c)? {
                    vision.overflowed |= vision.players.try_push(player).is_err();
                }
            }
            Child::List("L") => {
                let mut ends = ArrayVec::<Polar, 2>::new();
                loop {
                    match child(c)? {
                        Child::List("pol") => {
                            if let Some(end) = c.numbers::<3>()? {
                                let _ = ends.try_push(polar(end));
                            }
                        }
                        Child::List(_) => c.leave()?,
                        Child::Atom(_) => {}
                        Child::End => break,
                    }
                }
                if let [from, to] = ends[..] {
                    vision.overflowed |= vision.lines.try_push(SeenLine { from, to }).is_err();
                }
            }
            Child::List("B") => vision.ball = first_polar(c)?,
            Child::List(name) => {
                if let Some(at) = first_polar(c)? {
                    vision.overflowed |= vision.landmarks.try_push(Seen { name, at }).is_err();
                }
            }
            Child::Atom(_) => {}
            Child::End => return Ok(()),
        }
    }
}

fn read_player<'a>(c: &mut Cursor<'a>) -> Result<Option<SeenPlayer<'a>>, SexpError> {
    let (mut team, mut unum) = ("", None);
    let mut parts = ArrayVec::new();
    loop {
        match child(c)? {
            Child::List("team") => team = c.value()?.unwrap_or(""),
            Child::List("id") => unum = c.value()?.and_then(|v| v.parse().ok()),
            Child::List(name) => {
                if let Some(at) = first_polar(c)? {
                    // A robot has no more parts than this; extra ones would be a server's
                    // invention.
                    let _ = parts.try_push(Seen { name, at });
                }
            }
            Child::Atom(_) => {}
            Child::End => break,
        }
    }
    Ok(unum.map(|unum| SeenPlayer { team, unum, parts }))
}

/// rcssservermj: `(MIC hear (az b64) (az b64) …)`.
fn read_mic<'a>(
    c: &mut Cursor<'a>,
    heard: &mut ArrayVec<Heard<'a>, MAX_HEARD>,
) -> Result<bool, SexpError> {
    let mut whole = true;
    loop {
        match child(c)? {
            Child::List(azimuth) => {
                let text = c.value()?;
                if let (Some(az), Some(message)) = (parse_finite(azimuth), text) {
                    whole &= heard
                        .try_push(Heard {
                            team: None,
                            time: None,
                            from: HeardFrom::Direction(az),
                            message,
                        })
                        .is_ok();
                }
            }
            Child::Atom(_) => {}
            Child::End => return Ok(whole),
        }
    }
}

/// SimSpark: `(hear TEAM T self|DIR MSG)`, or the older `(hear T self|DIR MSG)`.
fn read_hear<'a>(c: &mut Cursor<'a>) -> Result<Option<Heard<'a>>, SexpError> {
    let mut atoms = [""; 4];
    let mut count = 0;
    let mut well_formed = true;
    loop {
        match child(c)? {
            Child::Atom(atom) => {
                match atoms.get_mut(count) {
                    Some(slot) => *slot = atom,
                    None => well_formed = false,
                }
                count += 1;
            }
            Child::List(_) => {
                c.leave()?;
                well_formed = false;
            }
            Child::End => break,
        }
    }
    let (team, rest) = match count {
        4 if well_formed => (Some(atoms[0]), &atoms[1..]),
        3 if well_formed => (None, &atoms[..3]),
        _ => return Ok(None),
    };
    let from = match rest[1] {
        "self" => HeardFrom::Myself,
        dir => parse_finite(dir).map_or(HeardFrom::Unknown(dir), HeardFrom::Direction),
    };
    Ok(Some(Heard {
        team,
        time: parse_finite(rest[0]),
        from,
        message: rest[2],
    }))
}
