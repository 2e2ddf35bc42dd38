// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/backends/cycle_clock.hpp"

#include <cmath>

namespace ameoto {

CycleClock::CycleClock(double nominal_rate) : nominal_rate_(nominal_rate), ns_per_frame_(1e9 / nominal_rate) {}

void CycleClock::reset() {
    ratio_ = 1.0;
    ratio_started_ = false;
    started_ = false;
    has_slope_ = false;
}

void CycleClock::update_ratio(const CycleReading& r) {
    if (r.period_usecs <= 0.0f) return;
    const double measured = static_cast<double>(r.frames) / (static_cast<double>(r.period_usecs) * 1e-6 * nominal_rate_);
    if (!(measured > 0.99 && measured < 1.01)) return;
    const double period_s = static_cast<double>(r.frames) / nominal_rate_;
    const double alpha = period_s / kAveragingSeconds > 1.0 ? 1.0 : period_s / kAveragingSeconds;
    ratio_ = ratio_started_ ? ratio_ + alpha * (measured - ratio_) : measured;
    ratio_started_ = true;
}

void CycleClock::restart_envelope(const CycleReading& r) {
    // The rate survives an xrun (the card's crystal did not change): the last slope of the envelope's own
    // carries the new one until it has 2 s again, in ns per frame from the nominal period.
    if (started_ && full_ >= kSlopeBuckets) {
        double mx = 0.0, mr = 0.0;
        fit_line(mx, mr, slope_);
        has_slope_ = true;
    }
    started_ = true;
    fit_valid_ = false;
    anchor_ns_ = r.callback_mono_ns;
    x_ = 0;
    full_ = 0;
    head_ = 0;
    current_has_ = false;
    high_since_x_ = -1;
    current_end_x_ = static_cast<std::int64_t>(std::llround(kBucketSeconds * nominal_rate_));
}

// The least-squares slope through the full buckets, leaving out bucket `skip` (an index into ring_, or
// -1), and the mean (x, r) of those it used.
double CycleClock::fit_slope(int skip, double& mx, double& mr) const {
    double n = 0.0;
    mx = 0.0;
    mr = 0.0;
    for (int i = 0; i < full_; ++i) {
        if (i == skip) continue;
        n += 1.0;
        mx += ring_[i].x;
        mr += ring_[i].r;
    }
    mx /= n;
    mr /= n;
    double sxx = 0.0, sxr = 0.0;
    for (int i = 0; i < full_; ++i) {
        if (i == skip) continue;
        sxx += (ring_[i].x - mx) * (ring_[i].x - mx);
        sxr += (ring_[i].x - mx) * (ring_[i].r - mr);
    }
    return sxx > 0.0 ? sxr / sxx : 0.0;
}

// The line through the full buckets' minima: their least-squares line once there are 2 s of them, the
// bucket lying highest above a first fit left out once when it is an outlier (a half second in which
// every callback was late says nothing about the line); before that, their centroid with the slope
// from before a restart, or at a start JACK's averaged rate. slope: ns per frame beyond the nominal.
void CycleClock::fit_line(double& mx, double& mr, double& slope) const {
    slope = fit_slope(-1, mx, mr);
    if (full_ < kSlopeBuckets) {
        slope = has_slope_ ? slope_ : ns_per_frame_ * (1.0 / ratio_ - 1.0);
        return;
    }
    int worst = -1;
    double worst_residual = kOutlierNs;
    for (int i = 0; i < full_; ++i) {
        const double residual = ring_[i].r - (mr + slope * (ring_[i].x - mx));
        if (residual > worst_residual) {
            worst_residual = residual;
            worst = i;
        }
    }
    if (worst >= 0) slope = fit_slope(worst, mx, mr);
}

double CycleClock::line_at(double x) {
    // Before the first bucket is full: the lowest reading so far.
    if (full_ == 0) return current_has_ ? current_.r : 0.0;
    // The fit changes only when a bucket joins or the envelope restarts, except while its slope is
    // still JACK's averaged rate, which moves every block: so it is fitted once a bucket, not twice a block.
    if (!fit_valid_ || (full_ < kSlopeBuckets && !has_slope_)) {
        fit_line(fit_.mx, fit_.mr, fit_.slope);
        fit_valid_ = true;
    }
    return fit_.mr + fit_.slope * (x - fit_.mx);
}

BlockTime CycleClock::block(const CycleReading& r) {
    update_ratio(r);
    if (!started_ || r.xrun || r.jack_frame != next_jack_frame_) restart_envelope(r);

    double reading = static_cast<double>(r.callback_mono_ns - anchor_ns_) - static_cast<double>(x_) * ns_per_frame_;
    // Time lost with no xrun reported: a quarter second of readings, every one far above the line.
    if (full_ > 0 || current_has_) {
        if (reading - line_at(static_cast<double>(x_)) <= kLostNs) {
            high_since_x_ = -1;
        } else {
            if (high_since_x_ < 0) high_since_x_ = x_;
            if (static_cast<double>(x_ - high_since_x_) >= kLostSeconds * nominal_rate_) {
                restart_envelope(r);
                reading = 0.0;
            }
        }
    }
    if (!current_has_ || reading < current_.r) {
        current_ = {static_cast<double>(x_), reading};
        current_has_ = true;
    }

    const double line = line_at(static_cast<double>(x_));
    BlockTime t;
    t.valid = true;
    t.rate_ratio = ratio_;
    t.unix_ns = anchor_ns_ + static_cast<std::int64_t>(std::llround(static_cast<double>(x_) * ns_per_frame_ + line)) + r.wall_minus_mono_ns;

    // The next block: JACK's counter and ours move on by this block; a full bucket joins the ring.
    next_jack_frame_ = r.jack_frame + r.frames;
    x_ += r.frames;
    if (x_ >= current_end_x_) {
        ring_[head_] = current_;
        head_ = (head_ + 1) % kBuckets;
        if (full_ < kBuckets) ++full_;
        fit_valid_ = false;
        current_has_ = false;
        current_end_x_ += static_cast<std::int64_t>(std::llround(kBucketSeconds * nominal_rate_));
    }
    return t;
}

}  // namespace ameoto
