#pragma once

#include <string>
#include <vector>

#include "core/paper_workload.hpp"
#include "core/policy_kind.hpp"
#include "gateway/sim/simulation.hpp"

namespace tgw::sim {

/// tm-sim's output: per-type delivery for one policy over several links, as Markdown.
class ResultTable {
  public:
    ResultTable(std::vector<core::MessageStream> workload, core::PolicyKind policy, double duration_s);

    void add(std::string link_name, SimulationResult result);

    /// A table per link: offered, on time, late, lost, logged by reason, mean and standard deviation.
    std::string detailed_markdown() const;
    /// One row per link: percent on time per type, and mean transmission time.
    std::string summary_markdown() const;

  private:
    /// The serialized bytes, in bits, of the samples that arrived in time.
    double on_time_payload_bits(const SimulationResult& result) const;

    std::vector<core::MessageStream> workload_;
    core::PolicyKind policy_;
    double duration_s_;
    std::vector<std::pair<std::string, SimulationResult>> rows_;
};

}  // namespace tgw::sim
