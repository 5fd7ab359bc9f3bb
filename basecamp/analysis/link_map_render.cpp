#include "basecamp/analysis/link_map_render.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "base/config_error.hpp"

namespace tgw::basecamp {

namespace {

constexpr double MARGIN_LEFT = 90, MARGIN_RIGHT = 190, MARGIN_TOP = 80, MARGIN_BOTTOM = 70;
constexpr double PATH_WIDTH = 5;
const Rgb NO_RATE{0.6, 0.6, 0.6};  // before the first status

/// A round step between grid lines: 1, 2 or 5 times a power of ten, about `span` / 8.
double grid_step(double span) {
    const double raw = span / 8;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0}) {
        if (m * power >= raw)
            return m * power;
    }
    return 10 * power;
}

std::string number_text(double value, const char* format) {
    char text[64];
    std::snprintf(text, sizeof text, format, value == 0 ? 0.0 : value);  // no "-0"
    return text;
}

/// A drop mark's radius in pixels: its area grows with the samples.
double drop_radius(std::uint64_t samples) {
    return 3 + 2.5 * std::sqrt(static_cast<double>(samples));
}

void text_at(cairo_t* cr, const std::string& text, double x, double y, double size, double align_x = 0,
             double align_y = 0) {
    cairo_set_font_size(cr, size);
    cairo_text_extents_t extents;
    cairo_text_extents(cr, text.c_str(), &extents);
    cairo_move_to(cr, x - extents.width * align_x - extents.x_bearing,
                  y - extents.height * align_y - extents.y_bearing);
    cairo_show_text(cr, text.c_str());
}

/// A drop mark: a see-through disc, so that the path under it shows.
void drop_disc(cairo_t* cr, double x, double y, double radius) {
    cairo_set_line_width(cr, 1.5);
    cairo_new_sub_path(cr);  // no line from where the last drawing ended
    cairo_arc(cr, x, y, radius, 0, 2 * M_PI);
    cairo_set_source_rgba(cr, 0.1, 0.1, 0.35, 0.25);
    cairo_fill_preserve(cr);
    cairo_set_source_rgba(cr, 0.1, 0.1, 0.35, 0.8);
    cairo_stroke(cr);
}

void set(cairo_t* cr, const Rgb& c) {
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
}

}  // namespace

Rgb rate_colour(double rate_bps, double min_bps, double max_bps) {
    const double t = max_bps > min_bps ? std::clamp((rate_bps - min_bps) / (max_bps - min_bps), 0.0, 1.0) : 1.0;
    // red (0.85, 0.1, 0.1) -> yellow (0.95, 0.8, 0.1) -> green (0.1, 0.65, 0.2)
    if (t < 0.5) {
        const double u = t / 0.5;
        return {0.85 + 0.10 * u, 0.10 + 0.70 * u, 0.10};
    }
    const double u = (t - 0.5) / 0.5;
    return {0.95 - 0.85 * u, 0.80 - 0.15 * u, 0.10 + 0.10 * u};
}

void render_link_map(const LinkMap& map, const std::string& title, const std::string& path, const std::string& flag,
                     int width, int height) {
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), &cairo_surface_destroy);
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> context(cairo_create(surface.get()), &cairo_destroy);
    cairo_t* cr = context.get();
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

    // Metres to pixels: the path's extent, padded, at one scale for x and y.
    double min_x = map.segments.front().from.x, max_x = min_x, min_y = map.segments.front().from.y, max_y = min_y;
    for (const MapSegment& s : map.segments) {
        for (const MapPoint& p : {s.from, s.to}) {
            min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
            min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
        }
    }
    const double pad = std::max({max_x - min_x, max_y - min_y, 1.0}) * 0.05;
    min_x -= pad, max_x += pad, min_y -= pad, max_y += pad;
    const double plot_w = width - MARGIN_LEFT - MARGIN_RIGHT, plot_h = height - MARGIN_TOP - MARGIN_BOTTOM;
    const double scale = std::min(plot_w / (max_x - min_x), plot_h / (max_y - min_y));
    const double left = MARGIN_LEFT + (plot_w - scale * (max_x - min_x)) / 2;
    const double bottom = MARGIN_TOP + plot_h - (plot_h - scale * (max_y - min_y)) / 2;
    const auto px = [&](double x) { return left + (x - min_x) * scale; };
    const auto py = [&](double y) { return bottom - (y - min_y) * scale; };

    // Grid and axes, in metres.
    const double step = grid_step(std::max(max_x - min_x, max_y - min_y));
    cairo_set_line_width(cr, 1);
    for (double x = std::ceil(min_x / step) * step; x <= max_x; x += step) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, px(x), py(min_y));
        cairo_line_to(cr, px(x), py(max_y));
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        text_at(cr, number_text(x, "%.0f"), px(x), py(min_y) + 8, 13, 0.5, 0);
    }
    for (double y = std::ceil(min_y / step) * step; y <= max_y; y += step) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, px(min_x), py(y));
        cairo_line_to(cr, px(max_x), py(y));
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        text_at(cr, number_text(y, "%.0f"), px(min_x) - 8, py(y), 13, 1, 0.5);
    }
    cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
    cairo_rectangle(cr, px(min_x), py(max_y), px(max_x) - px(min_x), py(min_y) - py(max_y));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text_at(cr, "x (m)", (px(min_x) + px(max_x)) / 2, py(min_y) + 34, 15, 0.5, 0);
    cairo_save(cr);
    cairo_translate(cr, px(min_x) - 55, (py(min_y) + py(max_y)) / 2);
    cairo_rotate(cr, -M_PI / 2);
    text_at(cr, "y (m)", 0, 0, 15, 0.5, 0.5);
    cairo_restore(cr);

    // The path, each stretch in the colour of its rate.
    cairo_set_line_width(cr, PATH_WIDTH);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (const MapSegment& s : map.segments) {
        set(cr, s.rate_bps ? rate_colour(*s.rate_bps, map.min_rate_bps, map.max_rate_bps) : NO_RATE);
        cairo_move_to(cr, px(s.from.x), py(s.from.y));
        cairo_line_to(cr, px(s.to.x), py(s.to.y));
        cairo_stroke(cr);
    }
    // The start: a ring.
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, 2);
    cairo_new_sub_path(cr);
    cairo_arc(cr, px(map.segments.front().from.x), py(map.segments.front().from.y), 9, 0, 2 * M_PI);
    cairo_stroke(cr);
    text_at(cr, "start", px(map.segments.front().from.x) + 12, py(map.segments.front().from.y) - 12, 13);

    // Where samples stayed on the robot: a disc whose area counts them.
    for (const DropMark& d : map.drops)
        drop_disc(cr, px(d.x), py(d.y), drop_radius(d.samples));

    // The colour scale, in kbit/s, and the legend.
    const double bar_x = width - MARGIN_RIGHT + 50, bar_top = MARGIN_TOP + 30, bar_h = plot_h * 0.6, bar_w = 24;
    for (int i = 0; i < static_cast<int>(bar_h); ++i) {
        const double rate = map.max_rate_bps - (map.max_rate_bps - map.min_rate_bps) * i / bar_h;
        set(cr, rate_colour(rate, map.min_rate_bps, map.max_rate_bps));
        cairo_rectangle(cr, bar_x, bar_top + i, bar_w, 1.5);
        cairo_fill(cr);
    }
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text_at(cr, "sensed rate", bar_x - 10, bar_top - 22, 14);
    for (int i = 0; i <= 4; ++i) {
        const double rate = map.max_rate_bps - (map.max_rate_bps - map.min_rate_bps) * i / 4;
        text_at(cr, number_text(rate / 1000, "%.1f kbit/s"), bar_x + bar_w + 6, bar_top + bar_h * i / 4, 12, 0, 0.5);
    }
    const double legend_y = bar_top + bar_h + 50;
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text_at(cr, "dropped on the robot", bar_x - 10, legend_y - 20, 13);
    double y = legend_y;
    for (const std::uint64_t n : {1, 10, 50}) {
        const double r = drop_radius(n);
        drop_disc(cr, bar_x + 12, y + r, r);
        cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
        text_at(cr, std::to_string(n) + (n == 1 ? " sample" : " samples"), bar_x + 40, y + r, 12, 0, 0.5);
        y += 2 * r + 10;
    }

    text_at(cr, title, MARGIN_LEFT, 30, 20);
    text_at(cr,
            std::to_string(map.poses) + " poses; " + std::to_string(map.rate_points) + " rates from " + map.rates_from +
                "; " + std::to_string(map.dropped_samples) + " samples dropped on the robot (from " + map.drops_from +
                ")",
            MARGIN_LEFT, 56, 14);

    cairo_surface_flush(surface.get());
    if (cairo_surface_write_to_png(surface.get(), path.c_str()) != CAIRO_STATUS_SUCCESS)
        throw base::ConfigError(flag + ": cannot write '" + path + "'");
}

}  // namespace tgw::basecamp
