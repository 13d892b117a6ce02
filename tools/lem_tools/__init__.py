"""Python layer of lem3d: reading the drivers' results, the analysis of the
paper (Affes et al. 2012), its figures and the parametric-study driver.

Modules:
  errors         ToolError, the base of every error a command reports
  files          the one atomic writer (temporary name, then rename)
  phases         the bond-phase names, in lem::Phase order
  results        the one reader of result files (CSV, JSON, HDF5)
  analysis       tail exponent beta, eq. 10 fit, K_c^r, replicate means, estimates
                 (no plotting)
  paper          the paper's values that the figures mark, in their units
  plotting       matplotlib set-up and the paper's star marks, shared by the figures
  cli            argparse set-up and error reporting shared by the commands
  plot_*         one figure command each
  study          study file, runs, status; the `study.py` command
  study_axes     a study's bond-count and replicate axes, the lattices they make
  study_table    results.csv and fit.json of a study (gather)
  study_plots    the study's figures
  convergence    replicate statistics, the fit in L_n and its extrapolation (no plotting)
  convergence_table  samples.csv, convergence*.csv and convergence.md (gather)
  convergence_plots  the convergence figures (paper fig. 6 extended)

The commands are run through the scripts next to this package
(tools/plot_fracture.py, tools/study.py, ...), each with --help.
"""
