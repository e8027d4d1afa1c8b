// Views of a model the way BRDF Explorer users look at one (Burley 2012, "Physically-Based Shading at Disney",
// section 2: the incidence-plane lobes, the albedo curve, the theta_h x theta_d image slice, a lit sphere), for
// one or several models side by side. Every figure is a PNG with the CSV it was drawn from.
//
// The plotted quantity is the model's value divided by NoL, i.e. pi * f_r (1 for a white Lambert surface at any
// angle), so lobes of different models compare at the same scale; the albedo curve is the directional albedo
// rho(theta_i) = (1 / pi) * integral of (value / NoL) * NoV over the viewing hemisphere. Curves and slices come
// from the double references (what the model computes, without float rounding); the lit sphere is rendered by
// the model's kernel.
#pragma once
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "models/material.hpp"

namespace shadelab::view {

struct ViewModel {
    std::string label;   // legend entry: the model name, with its parameters when they are not the defaults
    Material material;   // resolved, albedo 1 (grey)
};

struct ViewOptions {
    std::vector<double> incidence_deg{0.0, 30.0, 60.0, 75.0};   // one polar panel per incidence angle
    int polar_steps = 361;      // outgoing angles from -90 to 90 degrees in the incidence plane
    int albedo_steps = 90;      // incidence angles 0 .. 89 degrees
    int quadrature = 96;        // cells per axis of the albedo quadrature (cos theta_r x phi)
    int slice_size = 128;       // theta_h x theta_d image, pixels per side
    double slice_phi_d_deg = 90.0;
    int sphere_size = 256;
    double sphere_phase_deg = 45.0;   // angle between light and viewer for the lit sphere
};

struct ViewFiles {
    std::vector<std::string> written;   // every PNG and CSV, in the order written
};

// Writes polar.csv/png, albedo.csv/png, slice_<i>.csv and slices.png, sphere_<i>.png and spheres.png into `dir`.
ViewFiles write_views(Runtime& rt, const std::vector<ViewModel>& models, const std::string& dir,
                      const ViewOptions& options = {});

}  // namespace shadelab::view
