"""The track: rail model, line geometry and irregularity profiles."""
