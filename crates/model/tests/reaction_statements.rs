//! `reaction NAME: hinge|contact|rope P on B… [normal|along n]`: what it parses and checks into,
//! and its errors with line and column.

use model::{Diagnostic, ReleaseMember};

const PRELUDE: &str = "coordinates x, theta\nparameters m = 1, l = 1, g = 9.81\nframe N\n\
point A = x*N.x\npoint B = A + l*sin(theta)*N.x - l*cos(theta)*N.y\nparticle A mass m\n\
particle B mass m\ngravity -g*N.y\n";

fn diagnostics(source: &str) -> Vec<Diagnostic> {
    match model::load(source) {
        Ok(_) => Vec::new(),
        Err(errors) => errors.0,
    }
}

#[test]
fn hinge_contact_and_rope_check_into_releases() {
    let source = format!(
        "{PRELUDE}reaction pin: hinge A on B\nreaction track: contact A on A, B normal N.y\n\
         reaction pull: rope B on B along A - B\n"
    );
    let model = model::load(&source).expect("valid");
    let releases = model.releases();
    assert_eq!(releases.len(), 3);
    assert_eq!(releases[0].name.name, "pin");
    assert_eq!(releases[0].members, vec![ReleaseMember::Particle(1)]);
    assert!(releases[0].direction.is_none());
    assert_eq!(
        releases[1].members,
        vec![ReleaseMember::Particle(0), ReleaseMember::Particle(1)]
    );
    assert!(releases[2].direction.is_some());
}

#[test]
fn an_unknown_point_is_named_with_its_position() {
    let source = format!("{PRELUDE}reaction pin: hinge Q on B\n");
    let found = diagnostics(&source);
    let d = found
        .iter()
        .find(|d| d.kind.code() == "E313")
        .expect("E313");
    assert_eq!(d.message(), "reaction at unknown point `Q`");
    let at = d.line_col(&source);
    assert_eq!((at.line, at.column), (9, 21));
}

#[test]
fn a_member_must_be_a_body_or_a_particle() {
    let source = format!("{PRELUDE}reaction pin: hinge A on theta\n");
    let found = diagnostics(&source);
    let d = found
        .iter()
        .find(|d| d.kind.code() == "E314")
        .expect("E314");
    assert_eq!(
        d.message(),
        "`theta` is not a body or a particle: a reaction acts on bodies and particles"
    );
    let at = d.line_col(&source);
    assert_eq!((at.line, at.column), (9, 26));
}

#[test]
fn a_contact_needs_its_normal() {
    let source = format!("{PRELUDE}reaction n: contact A on A\n");
    let found = diagnostics(&source);
    assert!(
        found.iter().any(|d| d.message().contains("`normal`")),
        "{found:#?}"
    );
}

#[test]
fn the_old_reactions_list_still_parses() {
    let source = format!("{PRELUDE}constraint rail: x = 0\nreactions rail\n");
    let model = model::load(&source).expect("valid");
    assert_eq!(model.reactions().len(), 1);
    assert!(model.releases().is_empty());
}

#[test]
fn a_rolling_reaction_names_a_rolling_constraint() {
    let rolling =
        "coordinates x, phi\nparameters m = 1, R = 1\nframe N\nframe D = N rotated -phi about z\n\
                   point C = x*N.x + R*N.y\npoint A = x*N.x\n\
                   body disk mass m at C frame D inertia 1, 1, 1\n\
                   constraint roll: rolling disk at A\nconstraint rail: x = phi\n";
    let good = format!("{rolling}reaction contact: rolling roll normal N.y\n");
    let model = model::load(&good).expect("valid");
    let release = &model.releases()[0];
    assert!(release.constraint.is_some());
    assert_eq!(release.members.len(), 1);
    let bad = format!("{rolling}reaction contact: rolling rail normal N.y\n");
    let found = diagnostics(&bad);
    let d = found
        .iter()
        .find(|d| d.kind.code() == "E315")
        .expect("E315");
    assert_eq!(d.message(), "`rail` is not a rolling constraint");
    let at = d.line_col(&bad);
    assert_eq!((at.line, at.column), (10, 27));
}
