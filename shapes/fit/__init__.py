"""Primitive fitting: numpy RANSAC for sphere, cylinder, cone and plane, and the shape choice."""

from shapes.fit.select import ClusterFit, FitParams, estimate_normals, fit_cluster, pitt_choice

__all__ = ["ClusterFit", "FitParams", "estimate_normals", "fit_cluster", "pitt_choice"]
