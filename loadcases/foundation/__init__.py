"""The foundations every other part of `loadcases` stands on, importing nothing above them:
problems as data (`diagnostics`), input limits and quoting (`limits`, `clip`), the accuracy
target's default and bounds (`accuracy_target`), quantities (`units`, `unit_table`), files
written whole (`atomic`), cache folders (`cache_env`), the engine's source hash
(`engine_hash`), signals (`interrupts`) and a solving process's settings
(`process_settings`). Import from the modules; this package exports nothing."""
