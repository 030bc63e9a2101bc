"""Studies: many virtual surveys that vary named parameters, with replicates.

A study file (``designer-study-1.0.xsd``) names a base project, the factors to vary,
the design and the replicates; ``designer study run`` writes one project per variant,
renders each distinct image set once, reconstructs and compares each distinct
processing once, and tabulates and plots accuracy against its cost.
"""
