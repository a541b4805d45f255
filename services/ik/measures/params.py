"""The measures' coefficients: a message, defined with the others in shared."""

from shared.messages.measure_params import MeasureParams

__all__ = ["MeasureParams"]
