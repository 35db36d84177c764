// model.lumped, each field declared once (scenario/parameter_table.hpp).
#include "needlesim/engines/lumped/lumped_section.hpp"

#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {
namespace {

using Spec = LumpedModelSpec;

const scenario::ParamTable<Spec>& table() {
  using namespace scenario;
  namespace D = units::dim;
  static const auto t = ParamTable<Spec>("lumped").quantity(
      &Spec::relaxation_time, "relaxation_time", D::Time, "s", nonNegative(),
      "decay time of the friction held during a pause (0 = held)");
  return t;
}

}  // namespace

const scenario::ModelSection& lumpedSection() {
  static const scenario::ModelSection s{
      "lumped", "parameters of the lumped force model", [] { return table().docs(); },
      [](scenario::Section& sec, Scenario& sc) { table().read(sec, sc.model.lumped, sc); }};
  return s;
}

}  // namespace needlesim::engines
