"""Human text: words that agree with the numbers they follow."""

from shared.text.counted import agreeing, counted

__all__ = ["agreeing", "counted"]
