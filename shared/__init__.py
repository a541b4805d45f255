"""The common package every armplan process imports."""
