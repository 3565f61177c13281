// nodetrace.simulate(): see simulate.cpp. Its handling of cachesim run's
// options and report, shared with render(simulate=...).
#pragma once

#include <pybind11/pybind11.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/cachesim/simulation/simulation.hpp"

namespace nodetrace::python {

void bind_simulate(pybind11::module_& module);

// Cachesim run's options as its words: a text as a command line gives it,
// a list of words, or a dict (keyword names); `name` names the argument in
// errors.
std::vector<std::string> simulation_words(const pybind11::object& options, const std::string& name);

// The options `parse` reads (a parser of cachesim run's options that prints
// its error as "NAME: MESSAGE"), for a report of rows: its error raised as
// ValueError with the message, and --format refused (the rows are returned).
cachesim::SimulationOptions parse_simulation_options(
    const std::string& name, const std::function<std::optional<int>(cachesim::SimulationOptions&)>& parse);

// The report's rows and notes as a nodetrace.SimulationRows (the report in
// JSON: parse_simulation_options' options).
pybind11::object report_rows(const cachesim::SimulationReport& report);

}  // namespace nodetrace::python
