//! `-contact_pair`: two elastic bodies in contact ([`crate::contact::mortar`]).

use super::declared::*;
use super::{ContactSettings, NormalMode, Obstacle};
use crate::error::{bad, Error};

/// `-contact_pair`: (slave, master) pairs of surface groups.
pub(super) fn contact_pairs() -> Result<Option<Vec<(String, String)>>, Error> {
    let Some(words) = CONTACT_PAIR.words()? else {
        return Ok(None);
    };
    if words.len() % 2 != 0 {
        return bad(format!(
            "option -contact_pair: {} names given; pairs take two each (SLAVE,MASTER[,SLAVE2,MASTER2...])",
            words.len()
        ));
    }
    let pairs: Vec<(String, String)> = words
        .chunks(2)
        .map(|p| (p[0].clone(), p[1].clone()))
        .collect();
    if let Some(p) = pairs.iter().find(|p| p.0 == p.1) {
        return bad(format!(
            "option -contact_pair: '{}' is both the slave and the master surface of a pair",
            p.0
        ));
    }
    for (k, p) in pairs.iter().enumerate() {
        if let Some(q) = pairs[..k].iter().find(|q| q.0 == p.0) {
            return bad(format!(
                "option -contact_pair: '{}' is the slave surface of two pairs ({},{} and {},{}); a node meets one obstacle or one pair",
                p.0, q.0, q.1, p.0, p.1
            ));
        }
    }
    Ok(Some(pairs))
}

/// Contact between elastic bodies alone (no rigid obstacle): closest
/// normals (each slave node's own), no obstacle.
pub(super) fn pairs_only(pairs: Vec<(String, String)>) -> ContactSettings {
    ContactSettings {
        surfaces: Vec::new(),
        direction: Vec::new(),
        normal: NormalMode::Closest,
        obstacle: Obstacle::Plane { point: Vec::new() },
        obstacles: Vec::new(),
        named: false,
        pairs,
        pair_node_to_segment: false,
    }
}
