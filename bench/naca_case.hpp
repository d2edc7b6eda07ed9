#pragma once
// The benchmark case of the Core II issue, shared by the benchmarks: NACA 0012 (chord 1,
// leading edge at the origin) in a circular far field of radius 20 about (0.5, 0), with the
// paper's Fig. 10 density times s.

#include <string>

#include "meshd/core/domain.hpp"

namespace meshd::bench {

// `radius`: the far field's (examples/fig9.json has the same airfoil in one of radius 5).
inline core::DomainSpec naca_case_domain(double radius = 20.0) {
    using namespace meshd::core;
    DomainSpec s;
    s.points = {{"F", {0.5 + radius, 0.0}}};
    NacaSpec naca;
    naca.code = "0012";
    s.curves.push_back({"wing", naca, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back({"farfield", ArcShape{{0.5, 0.0}, ArcDirection::Ccw}, "F", "F", std::string("farfield")});
    s.loops = {{{"farfield", false}}, {{"wing", false}}};
    return s;
}

inline std::string naca_case_density(double s) {
    return "(x < 0.5 ? 0.1*sqrt(x^2+y^2)+0.007 : 0.1*sqrt((x-1.008930411365)^2+y^2)+0.006) * " + std::to_string(s);
}

}  // namespace meshd::bench
