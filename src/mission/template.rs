//! The commented mission template printed by `swarmctl template`.

/// A complete, valid mission documenting every field, its unit and its default.
pub const TEMPLATE: &str = include_str!("template.yaml");

#[cfg(test)]
mod tests {
    #[test]
    fn template_is_a_valid_mission() {
        let mission = super::super::from_yaml(super::TEMPLATE, "template.yaml".as_ref())
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(mission.drone_count(), 4);
    }
}
