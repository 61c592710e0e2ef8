"""Test configuration shared by every test module.

Under CI (``CI`` set in the environment, as ``.ci/run`` does) hypothesis runs
derandomized: the same examples every run, so a landing never depends on luck.
Locally it explores fresh examples each run, which is how it finds new bugs.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
