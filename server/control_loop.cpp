// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/control_loop.hpp"

#include <boost/asio/post.hpp>

#include <csignal>

namespace ameoto {

ControlLoop::ControlLoop() {
    stop_signals_.async_wait([this](const boost::system::error_code& ec, int) {
        if (!ec) shutdown();
    });
}

void ControlLoop::on_hangup(std::function<void()> handler) {
    on_hangup_ = std::move(handler);
    wait_hangup();
}

void ControlLoop::wait_hangup() {
    hangup_signal_.async_wait([this](const boost::system::error_code& ec, int) {
        if (ec) return;
        if (on_hangup_) on_hangup_();
        wait_hangup();
    });
}

void ControlLoop::every(std::chrono::steady_clock::duration period, std::function<void()> tick) {
    fire(timers_.emplace_back(Repeating{boost::asio::steady_timer(io_), period, std::move(tick)}));
}

void ControlLoop::fire(Repeating& r) {
    r.tick();
    if (stopping_) return;
    r.timer.expires_after(r.period);
    r.timer.async_wait([this, &r](const boost::system::error_code& ec) {
        if (!ec) fire(r);
    });
}

void ControlLoop::run() { io_.run(); }

void ControlLoop::shutdown() {
    if (stopping_) return;   // a signal, /quit and the end of --duration may all ask
    stopping_ = true;
    stop_signals_.cancel();
    hangup_signal_.cancel();
    for (Repeating& r : timers_) r.timer.cancel();
    for (const auto& handler : shutdown_handlers_) handler();
    io_.stop();
}

void ControlLoop::shutdown_soon() {
    boost::asio::post(io_, [this] { shutdown(); });
}

}  // namespace ameoto
