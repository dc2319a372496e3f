"""What the web views read: the memory graph, stored scenes, the episode timeline and channel
plots, as typed records for ``api/routes/views.py`` (and so for the OpenAPI).

Presentation only: every figure comes from the scene memory's public methods
(:class:`reasoners.memory.SceneMemory`), the episode memory, the store's own triples and the
stream files; nothing here writes. The pages themselves are static files in ``api/web/``.
"""
