// gyrocomp._core: the compiled half of the Python package (python/gyrocomp/__init__.py wraps the
// dicts returned here into result objects). docs/guides/python.md.
#include "bindings.h"

namespace gyrocomp::python {

PYBIND11_MODULE(_core, m) {
  m.doc() = "gyrocomp: MEMS gyro noise and temperature-drift removal (C++ library bindings)";
  m.attr("__version__") = GYROCOMP_VERSION;

  py::class_<CancellationToken>(m, "CancellationToken",
                                "Set from any thread (or a signal handler) to stop a long call at its next progress point.")
      .def(py::init<>())
      .def("cancel", &CancellationToken::Cancel)
      .def("reset", &CancellationToken::Reset)
      .def_property_readonly("cancelled", &CancellationToken::cancelled);
  static py::exception<Cancelled> cancelled_error(m, "Cancelled", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled& e) {
      PyErr_SetString(cancelled_error.ptr(), "cancelled by the CancellationToken");
    }
  });

  BindAllan(m);
  BindSimulator(m);
  BindStages(m);
  BindDrift(m);
  BindPipeline(m);
  BindExport(m);
  BindIo(m);
  BindCalibrate(m);
  BindPlan(m);
  BindInspect(m);
}

}  // namespace gyrocomp::python
