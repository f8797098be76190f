"""Long compiled loops hand back to Python every CHUNK_SECONDS or so.

Python handles Ctrl-C and SIGTERM only between two calls into compiled code, so
a time loop runs its steps in chunks: ``advance(first, last)`` runs steps
first..last and returns (a stop step or 0), and the chunk of steps starts at one
and doubles while a call takes under half of CHUNK_SECONDS (halves when one
takes more). A slow step (a stiff contact's friction sub-steps, a slow user
law) then still lets a signal end the run at once, while quick steps run in
chunks of thousands, at no measurable cost. The loops keep all their state in
arrays, so where a run is cut into chunks does not change its results.
"""

import time

CHUNK_SECONDS = 0.2


def next_chunk(chunk: int, took: float, ran: int) -> int:
    """The chunk after a call that ran ``ran`` steps (of ``chunk`` asked) in ``took`` s."""
    if took < CHUNK_SECONDS / 2 and ran == chunk:
        return 2 * chunk
    if took > CHUNK_SECONDS and chunk > 1:
        return chunk // 2
    return chunk


def run_in_chunks(steps: int, advance) -> int:
    """Run steps 1..steps by ``advance(first, last) -> stop step or 0`` in growing
    chunks (the module); returns the first stop step, or 0."""
    first, chunk = 1, 1
    while first <= steps:
        last = min(steps, first + chunk - 1)
        called = time.perf_counter()
        stop = advance(first, last)
        if stop:
            return stop
        chunk = next_chunk(chunk, time.perf_counter() - called, last - first + 1)
        first = last + 1
    return 0
