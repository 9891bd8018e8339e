"""YAML files read safely with the line and column of every key (`source`), and the parsed
trees kept in the user cache folder (`parse_cache`). Import from the modules; this package
exports nothing."""
