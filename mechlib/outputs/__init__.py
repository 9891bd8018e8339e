"""Outputs requested by name and evaluated on a recorded trajectory: joint reactions,
motion efforts, point kinematics, element outputs, expressions and the energy balance."""
