"""Comparing tyre models: with each other and with data (:mod:`.tyres`), and the
camber brush model against PAC89 (:mod:`.brush`)."""

from .tyres import Comparison, LoadComparison, binned_curve, compare_tyres, data_metrics, model_metrics

__all__ = ["Comparison", "LoadComparison", "compare_tyres", "model_metrics", "data_metrics", "binned_curve"]
