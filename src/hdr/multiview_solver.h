// The least-squares solve of the multi-view radiometric calibration (CalibrateMultiView) for
// one weight of the response prior: the exposure gauge, the robust reweighting and the
// result's figures. Internal to hdr.
#pragma once

#include <vector>

#include "hdr/multiview_calibration.h"

namespace hdribr {

// CalibrateMultiView for options.response_prior alone (its candidates unused), the options
// already validated. With options.per_channel_exposure, `scalar_log_exposure` holds per photo
// the log exposures of the same solve with one exposure per photo, to which the channels'
// offsets are held orthogonal; unused otherwise. Throws UsageError as CalibrateMultiView.
MultiViewCalibration SolveMultiView(const std::vector<MultiViewSample>& samples,
                                    const std::vector<double>& prior_log_exposure,
                                    const MultiViewOptions& options,
                                    const std::vector<double>& scalar_log_exposure = {});

}  // namespace hdribr
