"""Classification: labelled points in, a discriminating projection and class predictions out.

* :func:`lda` — Fisher's linear discriminant analysis (closed form);
* :func:`nca` — neighbourhood components analysis (gradient-based);
* :func:`as_labels` — the check of one class label per point both use (the service checks
  requests with it before they are queued).
"""

from algorithms.classification._common import as_labels
from algorithms.classification.lda import LDAResult, check_lda, lda
from algorithms.classification.nca import NCAResult, check_nca, nca

__all__ = ["LDAResult", "lda", "check_lda", "NCAResult", "nca", "check_nca", "as_labels"]
