#include "nodetrace/tracer/render/integrator.hpp"

namespace nodetrace::tracer {

std::string_view integrator_name(Integrator integrator) {
  return integrator == Integrator::Path ? "path" : "whitted";
}

std::optional<Integrator> parse_integrator(std::string_view name) {
  if (name == "whitted") return Integrator::Whitted;
  if (name == "path") return Integrator::Path;
  return std::nullopt;
}

std::string_view sampler_name(PathSampler sampler) {
  return sampler == PathSampler::Sobol ? "sobol" : "independent";
}

std::optional<PathSampler> parse_sampler(std::string_view name) {
  if (name == "independent") return PathSampler::Independent;
  if (name == "sobol") return PathSampler::Sobol;
  return std::nullopt;
}

}  // namespace nodetrace::tracer
