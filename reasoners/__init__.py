"""Reasoning over the knowledge graph.

- the scene memory (port of SIT and the memory reasoners): :mod:`reasoners.memory` with
  :class:`reasoners.memory.SceneMemory`, its parts in :mod:`reasoners.loading`,
  :mod:`reasoners.score_view`, :mod:`reasoners.transactions` and :mod:`reasoners.reads`, its
  inputs in :mod:`kg.primitive` and :mod:`reasoners.operations`, and its errors in
  :mod:`reasoners.errors`;
- OWL 2 RL materialisation: :mod:`reasoners.owl_rl`.
"""
