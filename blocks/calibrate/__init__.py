"""Calibration against measured data: ``vphs calibrate EXPERIMENT``.

One straight line, each step a small module:

- :mod:`~blocks.calibrate.experiment`: the experiment file (pydantic, located errors), values in SI;
- :mod:`~blocks.calibrate.data`: the measured columns mapped onto channels, noise given or estimated;
- :mod:`~blocks.calibrate.model`: predictions by simulation (``Circuit.simulate(overrides)`` only), the
  normalised residuals with the true inputs as latent values (errors-in-variables), finite differences;
- :mod:`~blocks.calibrate.fit`: weighted least squares (scipy ``least_squares``), standard errors;
- :mod:`~blocks.calibrate.stats`: lack of fit (chi^2/nu, Ljung-Box, cross-correlation, per-group drift);
- :mod:`~blocks.calibrate.run_start`: whether a time series's run starts off the data (its initial state);
- :mod:`~blocks.calibrate.heldout`: held-out error (leave one group out, k-fold);
- :mod:`~blocks.calibrate.candidates`: the library of candidate effects, one module each;
- :mod:`~blocks.calibrate.patch`: netlist edits written as new files;
- :mod:`~blocks.calibrate.screening`: the score test of every candidate at every place;
- :mod:`~blocks.calibrate.selection`: refits, BIC ranking, acceptance, ambiguity, a fit's local minimum;
- :mod:`~blocks.calibrate.run`: the rounds (fit, trace, augment; at most three traces);
- :mod:`~blocks.calibrate.verdict`: what the rounds found, in words;
- :mod:`~blocks.calibrate.report`: markdown, JSON and plots.
"""
