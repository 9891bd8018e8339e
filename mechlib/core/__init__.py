"""The foundations every layer shares: how a run ended (outcome), work counters, rotations,
the compiled-kernel decorator, lazy names and the cubic step. A leaf: it imports nothing of
mechlib outside itself."""
