"""What every coursework judge returns besides its figures: the failures, and so the verdict."""


class Judgement:
    """A judge's answer: a dataclass with its figures and failures (empty when it passed)."""

    failures: tuple[str, ...]

    @property
    def passed(self) -> bool:
        return not self.failures
