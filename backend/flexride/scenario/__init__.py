"""Scenario schemas: vehicle, track, line, contact, excitation, solver and outputs, with
units and bounds; presets; the one loader of scenario files, mappings and presets.
"""
