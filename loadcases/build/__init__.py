"""A validated case -> a `mechlib` model, its analysis, requests, elements, contacts and events."""
