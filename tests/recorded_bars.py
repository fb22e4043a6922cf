"""Progress bars recorded instead of drawn, for the tests of what a long computation shows
(``test_campbell_memory.py``, ``test_mode_number_progress.py``; both wrote this class)."""

from __future__ import annotations


class RecordedBars:
    """``tqdm.auto.tqdm`` replaced (through ``monkeypatch``) by a recorder of every bar made:
    ``made`` lists ``(description, bar)``, each bar with its ``total``, the sum of its updates
    ``counted`` and each update ``steps``; nothing is drawn."""

    def __init__(self, monkeypatch):
        import tqdm.auto

        self.made = []
        real = tqdm.auto.tqdm
        bars = self

        class Recorded(real):
            def __init__(self, *args, **kwargs):
                kwargs["disable"] = True
                super().__init__(*args, **kwargs)
                self.counted, self.steps = 0, []
                bars.made.append((kwargs.get("desc"), self))

            def update(self, n=1):
                self.counted += n
                self.steps.append(n)
                return super().update(n)

        monkeypatch.setattr(tqdm.auto, "tqdm", Recorded)

    def named(self, description):
        """``(total, counted)`` of each bar made with ``description``."""
        return [(bar.total, bar.counted) for desc, bar in self.made if desc == description]
