"""Classification: labelled points in, a discriminating projection and class predictions out.

* :func:`lda` — Fisher's linear discriminant analysis (closed form);
* :func:`nca` — neighbourhood components analysis (gradient-based).
"""

from algorithms.classification.lda import LDAResult, lda
from algorithms.classification.nca import NCAResult, nca

__all__ = ["LDAResult", "lda", "NCAResult", "nca"]
