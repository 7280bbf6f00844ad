// Levelled diagnostics: level names, attribution to a file, and the plain message list.
#include "core/diagnostic.hpp"

namespace lidarscout {

const char* level_name(DiagnosticLevel level) {
    switch (level) {
        case DiagnosticLevel::note: return "note";
        case DiagnosticLevel::warning: return "warning";
    }
    return "warning";
}

void Diagnostics::attribute_to(const std::string& file) {
    for (auto& d : items_) {
        if (d.file.empty()) d.file = file;
    }
}

std::vector<std::string> Diagnostics::messages() const {
    std::vector<std::string> out;
    out.reserve(items_.size());
    for (const auto& d : items_) out.push_back(d.message);
    return out;
}

}  // namespace lidarscout
