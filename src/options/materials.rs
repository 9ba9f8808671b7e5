//! A material per body: `-E_NAME`, `-nu_NAME`, `-density_NAME` override
//! the global `-E`, `-nu`, `-density` on the cells of body group NAME (a
//! physical group of the mesh's dimension). The values are checked here,
//! as the global ones are; the names against the mesh, and the cells
//! against two groups of different materials, once it is read
//! (`crate::fem::material`).
//!
//! `-E` and `-nu` stay required (and `-density` with `-gravity`): they are
//! the material of the cells of no body group, and the report's `E`, `nu`.

use super::declared::{real_of, DENSITY, DENSITY_BODY, GRAVITY, NU_BODY, YOUNG_BODY};
use super::{shown, Settings};
use crate::error::{bad, Error};

/// An isotropic linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Young's modulus.
    pub young: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Mass density (0 without `-density`: it only weighs with `-gravity`).
    pub density: f64,
}

impl Material {
    /// The P-wave modulus `lambda + 2 mu` (plane stress in 2D: `E / (1 - nu^2)`).
    pub fn p_wave_modulus(&self, dim: usize, plane_stress: bool) -> f64 {
        let (e, nu) = (self.young, self.nu);
        if dim == 2 && plane_stress {
            e / (1.0 - nu * nu)
        } else {
            e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
        }
    }

    /// A body's part of Hertz's E*: `E / (1 - nu^2)`, or `E` in plane
    /// stress (2D).
    pub fn hertz_modulus(&self, dim: usize, plane_stress: bool) -> f64 {
        if dim == 2 && plane_stress {
            self.young
        } else {
            self.young / (1.0 - self.nu * self.nu)
        }
    }
}

/// The options of one body group: what they override.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyMaterial {
    /// The physical group's name (NAME of `-E_NAME`).
    pub group: String,
    pub young: Option<f64>,
    pub nu: Option<f64>,
    pub density: Option<f64>,
}

impl BodyMaterial {
    /// The first of its options given, for messages: `-E_NAME`, else
    /// `-nu_NAME`, else `-density_NAME`.
    pub fn option(&self) -> String {
        let prefix = if self.young.is_some() {
            "-E_"
        } else if self.nu.is_some() {
            "-nu_"
        } else {
            "-density_"
        };
        format!("{prefix}{}", self.group)
    }

    /// The material of its cells: `global` with its overrides.
    pub fn over(&self, global: Material) -> Material {
        Material {
            young: self.young.unwrap_or(global.young),
            nu: self.nu.unwrap_or(global.nu),
            density: self.density.unwrap_or(global.density),
        }
    }
}

/// The materials of a scene: the global one and each body group's options.
#[derive(Clone, Debug, PartialEq)]
pub struct Materials {
    /// `-E`, `-nu`, `-density`: the cells of no body group.
    pub global: Material,
    /// One per body group named by an option, sorted by name.
    pub bodies: Vec<BodyMaterial>,
    /// `-gravity` (the body force of a cell is its density times it).
    pub gravity: Option<Vec<f64>>,
}

impl Materials {
    /// The global material alone (no body groups).
    pub fn uniform(young: f64, nu: f64) -> Materials {
        Materials {
            global: Material {
                young,
                nu,
                density: 0.0,
            },
            bodies: Vec::new(),
            gravity: None,
        }
    }

    /// Every material the options name: the global one, then each body's.
    pub fn all(&self) -> impl Iterator<Item = Material> + '_ {
        std::iter::once(self.global).chain(self.bodies.iter().map(|b| b.over(self.global)))
    }
}

/// `-nu` and `-nu_NAME` take a value in (-1, 0.5).
pub fn check_nu(name: &str, nu: f64) -> Result<f64, Error> {
    if !(nu > -1.0 && nu < 0.5) {
        return bad(format!("option {name}: {} is outside (-1, 0.5)", shown(nu)));
    }
    Ok(nu)
}

/// Reads `-E_NAME`, `-nu_NAME`, `-density_NAME` over the global `young`
/// and `nu` (checked already), each value checked as the global one is.
pub fn read(young: f64, nu: f64) -> Result<Materials, Error> {
    let mut m = Materials::uniform(young, nu);
    m.gravity = GRAVITY.vector()?;
    m.global.density = DENSITY.real()?.unwrap_or(0.0);
    let mut body = |group: &str| -> usize {
        match m.bodies.iter().position(|b| b.group == group) {
            Some(i) => i,
            None => {
                m.bodies.push(BodyMaterial {
                    group: group.to_string(),
                    young: None,
                    nu: None,
                    density: None,
                });
                m.bodies.len() - 1
            }
        }
    };
    let mut given = Vec::new();
    for (kind, family) in [(0, &YOUNG_BODY), (1, &NU_BODY), (2, &DENSITY_BODY)] {
        for (group, _) in family.members()? {
            let prefix = family.name.strip_suffix("NAME").unwrap_or(family.name);
            let name = format!("{prefix}{group}");
            let Some(v) = real_of(&name)? else {
                return bad(format!("option {name} needs a value"));
            };
            let v = match kind {
                0 if v <= 0.0 => {
                    return bad(format!("option {name}: {} is not positive", shown(v)))
                }
                1 => check_nu(&name, v)?,
                2 if v < 0.0 => return bad(format!("option {name}: {} is negative", shown(v))),
                2 if GRAVITY.vector()?.is_none() => {
                    return bad(format!(
                    "option {name} needs -gravity gx,gy[,gz] (the body force is density x gravity)"
                ))
                }
                _ => v,
            };
            given.push((body(&group), kind, v));
        }
    }
    for (i, kind, v) in given {
        let b = &mut m.bodies[i];
        match kind {
            0 => b.young = Some(v),
            1 => b.nu = Some(v),
            _ => b.density = Some(v),
        }
    }
    m.bodies.sort_by(|a, b| a.group.cmp(&b.group));
    Ok(m)
}

impl Settings {
    /// The stiffest material the options name (the largest P-wave
    /// modulus; the global one on a tie): the one modulus of the scales
    /// that need one for the whole scene (the trial r, r/E in the summary,
    /// the Hertz reference's E*).
    pub fn stiffest(&self, dim: usize) -> Material {
        let p = |m: &Material| m.p_wave_modulus(dim, self.plane_stress);
        self.materials.all().fold(self.materials.global, |best, m| {
            if p(&m) > p(&best) {
                m
            } else {
                best
            }
        })
    }

    /// E* of the Hertz formulas: the contact's, from the materials under
    /// its surfaces once the mesh is read
    /// ([`crate::fem::material::contact_e_star`]); before, or where the
    /// mesh holds none of the surfaces, E/(1-nu^2), or E in plane stress,
    /// of the stiffest material ([`Settings::stiffest`]: the global one
    /// when the options name no other).
    pub fn e_star(&self, dim: usize) -> f64 {
        if let Some(e) = self.contact_e_star {
            return e;
        }
        self.stiffest(dim).hertz_modulus(dim, self.plane_stress)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_and_options() {
        let global = Material {
            young: 1.0,
            nu: 0.3,
            density: 2.0,
        };
        let b = BodyMaterial {
            group: "hard".into(),
            young: None,
            nu: Some(0.25),
            density: None,
        };
        assert_eq!(b.option(), "-nu_hard");
        assert_eq!(
            b.over(global),
            Material {
                young: 1.0,
                nu: 0.25,
                density: 2.0
            }
        );
        assert!(check_nu("-nu_x", 0.5).is_err() && check_nu("-nu_x", -1.0).is_err());
        let steel = Material {
            young: 10.0,
            ..global
        };
        assert!(steel.p_wave_modulus(3, false) > global.p_wave_modulus(3, false));
    }
}
