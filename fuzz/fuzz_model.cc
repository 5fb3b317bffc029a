// libFuzzer harness: the drift-model file loader (DriftModelFromJson, what `apply -m` reads),
// and, when a model loads, a prediction over a few temperatures (what `apply` does next).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "gyrocomp/drift/drift_model.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  gyrocomp::Result<gyrocomp::DriftModel> model = gyrocomp::DriftModelFromJson(text, "fuzz.json");
  if (!model) return 0;
  const std::vector<double> temp_c = {-40.0, -10.0, 25.0, 25.5, 26.0, 60.0, 85.0, 85.0};
  (void)model->Predict(gyrocomp::DriftInputs{temp_c, 1.0});
  (void)model->CheckTemperatureRange(temp_c);
  return 0;
}
