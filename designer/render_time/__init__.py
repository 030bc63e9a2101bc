"""Render time: how long a render takes on this machine, and what a render's time is.

* :mod:`.model` — the one model behind every render estimate (``designer plan``, the
  GUI's panels, a study's summary), its coefficients per machine and per kind of render
  (the cache), their fit to measured frames, and how a duration is written;
* :mod:`.record` — after a render, its frames' fitted coefficients recorded for the next
  estimate of that kind;
* :mod:`.timing` — the timings of one render, each named for what it counts;
* :mod:`.stages` — the stages of a frame's render time, as the worker reports them.

The package sits below survey and render (it imports only :mod:`designer.core` and
:mod:`designer.project`): the plan's estimate and the render both use it. The probe render
of ``designer warmup`` is a render, so it lives in :mod:`designer.render.probe` and
stores its figures through :mod:`.record`.
"""
