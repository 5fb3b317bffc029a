// Everything gyrocomp offers, for users who want one include. Each stage also has its own
// header (include/gyrocomp/<stage>/<name>.h); including only what you use builds faster.
// Stages in the order data flows (docs/architecture.md).
#pragma once

#include "gyrocomp/core/status.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/allan/allan.h"
#include "gyrocomp/sim/simulator.h"
#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/decompose/feature_classifier.h"
#include "gyrocomp/denoise/wavelet.h"
#include "gyrocomp/denoise/wavelet_filters.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/denoise/wflp.h"
#include "gyrocomp/denoise/bandwidth.h"
#include "gyrocomp/drift/svr.h"
#include "gyrocomp/drift/cuckoo_search.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/temperature_rate.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/report/report.h"
