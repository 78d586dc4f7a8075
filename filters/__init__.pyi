# The one list of what `filters` exports: lazy_loader reads it at import (names are imported when first
# used) and type checkers read it as the package's interface.
from . import (blending as blending, curvature as curvature, denoise as denoise, fourier as fourier,
    inverse as inverse, masks as masks, padding as padding, smoothing as smoothing)
from ._checks import (MEMORY_ENV as MEMORY_ENV, TooLarge as TooLarge, as_image as as_image,
    as_weights as as_weights, check_memory as check_memory, memory_limit as memory_limit, positive as positive)
from .padding import (PAD_MODES as PAD_MODES, PERIODIC_MODES as PERIODIC_MODES, pad as pad,
    periodic_extension as periodic_extension)
from .masks import (apply_masked as apply_masked, feather as feather)
from .smoothing import (bilateral_filter as bilateral_filter, gaussian_filter as gaussian_filter,
    guided_filter as guided_filter, mean_filter as mean_filter)
from .denoise import (denoise_nl_means as denoise_nl_means, denoise_tv as denoise_tv,
    median_filter as median_filter)
from .fourier import (bandpass as bandpass, fourier_filter as fourier_filter, highpass as highpass,
    lowpass as lowpass)
from .inverse import (inverse_filter as inverse_filter, unsharp_mask as unsharp_mask)
from .blending import (blend as blend, composite as composite, paste as paste, resize as resize)
from .curvature import (grid_curvature as grid_curvature)
