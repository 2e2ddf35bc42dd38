// SPDX-License-Identifier: GPL-3.0-or-later
// Ameoto: control the ameotod rain server from SuperCollider over OSC (docs/PROTOCOL.md).
//
// Interface:
//   a = Ameoto("127.0.0.1", 7770);      // or Ameoto.new; a.connect(host, port) to move
//   a.rate_(30);                        // rain rate, mm/h 0..500 (ramps over 1 s)
//   a.wind_(6, 90, 0.3);                // speed m/s, direction degrees, gust 0..1
//   a.drop(4, 0, 0.2, 0.1);             // diameter mm, speed m/s (0 = terminal), x m, y m [, surface]
//   a.dropAt(0.5, 4, 0, 0.2, 0.1);      // the same drop in a bundle, 0.5 s from now, to the sample
//   a.liquid_(\milk); a.material_(\umbrella, \vinyl); a.scene_(\street); a.listener_(1, 0.5, 1.6, 30);
//   a.lod(50, 16); a.dsd_(\gamma, 2, 3); a.surfaceAdd(\roof, \plate, \tin, 1, 0.6, 0, 1, 3);
//   a.gain_(-6); a.loudness_(-18); a.level({ |l| l.fullScaleSPL.postln });   // level: docs/loudness.md
//   a.sync({ "applied".postln });        // /sync -> /synced; a.syncWait inside a Routine
//   a.status({ |s| s.active_drops_full.postln });    // an Event of the named /status.reply fields
//   a.notify_(true); a.onStatus = { |s| ... }; a.onMeter = { |msg| ... };   // subscriptions
//   a.version({ |msg| msg.postln }); a.query('/rain/rate', { |msg| msg.postln });
//   a.onFail = { |address, reason| ... };   // default: a warning in the post window
//   a.free;                             // removes every OSCFunc (disconnect is the same)
//
// Replies come back to sclang's own port (NetAddr.langPort): the server answers the port a request
// came from. Values go out as the units the protocol documents (mm, m, m/s, mm/h, degrees).

Ameoto {
	classvar <statusFields;
	var <addr, <responders, pendingStatus, pendingSync, nextSyncId = 1;
	var <>onFail, <>onDone, <>onStatus, <>onMeter;

	*initClass {
		// /status.reply ,fffiiiiififfsfif: the names `ameoto status --json` uses.
		statusFields = #[
			\cpu_average_percent, \cpu_peak_percent, \drops_per_second,
			\active_drops_full, \active_drops_template, \active_drops_texture,
			\xruns, \late_bundles, \sample_rate_hz, \block_size_frames,
			\seconds_rendered, \rain_rate_mm_per_h, \backend, \clock_ppm, \clipped_samples, \full_scale_db_spl
		];
	}

	*new { |host = "127.0.0.1", port = 7770|
		^super.new.init.connect(host, port)
	}

	init {
		responders = List.new;
		pendingStatus = List.new;
		pendingSync = IdentityDictionary.new;
		onFail = { |address, reason| "ameoto: % refused: %".format(address, reason).warn };
	}

	connect { |host = "127.0.0.1", port = 7770|
		this.disconnect;
		addr = NetAddr(host.asString, port.asInteger);
		responders.add(OSCFunc({ |msg| onFail.value(msg[1], msg[2]) }, '/fail', addr));
		responders.add(OSCFunc({ |msg| onDone.value(msg[1]) }, '/done', addr));
		responders.add(OSCFunc({ |msg| this.prStatusReply(msg) }, '/status.reply', addr));
		responders.add(OSCFunc({ |msg| this.prSynced(msg[1]) }, '/synced', addr));
		responders.add(OSCFunc({ |msg| onMeter.value(msg) }, '/meter', addr));
	}

	disconnect {
		responders.do(_.free);
		responders.clear;
		pendingStatus.clear;
		pendingSync.clear;
	}

	free { this.disconnect }

	// ---- the rain ----
	rate_ { |mmPerHour| addr.sendMsg('/rain/rate', mmPerHour.asFloat) }
	wind_ { |speed = 0, deg = 0, gust = 0|
		addr.sendMsg('/rain/wind', speed.asFloat, deg.asFloat, gust.asFloat)
	}
	dsd_ { |name = "marshall-palmer", mu, lambda|
		var args = [name.asString];
		if(mu.notNil) { args = args ++ [mu.asFloat, (lambda ? 0).asFloat] };
		addr.sendMsg('/rain/dsd', *args)
	}

	// ---- drops ----
	dropMsg { |diameterMM = 3, speed = 0, x = 0.2, y = 0, surface|
		var m = ['/drop', diameterMM.asFloat, speed.asFloat, x.asFloat, y.asFloat];
		^if(surface.notNil) { m ++ [surface.asString] } { m }
	}
	drop { |diameterMM = 3, speed = 0, x = 0.2, y = 0, surface|
		addr.sendMsg(*this.dropMsg(diameterMM, speed, x, y, surface))
	}
	// A bundle timed `delta` seconds after the current logical time: the server plays it at that sample.
	dropAt { |delta, diameterMM = 3, speed = 0, x = 0.2, y = 0, surface|
		addr.sendBundle(delta, this.dropMsg(diameterMM, speed, x, y, surface))
	}
	sendBundle { |delta ... msgs| addr.sendBundle(delta, *msgs) }
	sendMsg { |... msg| addr.sendMsg(*msg) }

	// ---- materials, scene, listener, detail ----
	liquid_ { |name = \water, density, surfaceTension, viscosity|
		var args = [name.asString];
		if(density.notNil) { args = args ++ [density, surfaceTension, viscosity].collect(_.asFloat) };
		addr.sendMsg('/material/liquid', *args)
	}
	material_ { |surface = \umbrella, name = \nylon, arealDensity, tension, massDamping, stiffnessDamping|
		var args = [surface.asString, name.asString];
		if(arealDensity.notNil) {
			args = args ++ [arealDensity, tension, massDamping, stiffnessDamping].collect(_.asFloat)
		};
		addr.sendMsg('/material/surface', *args)
	}
	// /scene/load: the address every ameotod version has (the protocol core's /scene is its alias).
	scene_ { |name| addr.sendMsg('/scene/load', name.asString) }
	saveScene { |name| addr.sendMsg('/scene/save', name.asString) }
	listener_ { |x = 0, y = 0, z = 1.6, facingDeg = 0|
		addr.sendMsg('/listener', x.asFloat, y.asFloat, z.asFloat, facingDeg.asFloat)
	}
	// The head turned within the body (a head tracker), degrees: yaw left, pitch nose up, roll right ear
	// down. Every format but ears: Ambisonics rotates the bus, stereo and rings re-pan every sound by its
	// turned direction, gliding over 256 samples (docs/output-formats.md, "Turning the head").
	orientation { |yawDeg = 0, pitchDeg = 0, rollDeg = 0|
		addr.sendMsg('/listener/orientation', yawDeg.asFloat, pitchDeg.asFloat, rollDeg.asFloat)
	}
	// action.value(event): yaw, pitch, roll (degrees) of the head as last applied; nil after timeout seconds.
	headOrientation { |action, timeout = 2|
		this.query('/listener/orientation', { |msg|
			action.value(msg !? { (yaw: msg[1], pitch: msg[2], roll: msg[3]) })
		}, timeout)
	}
	lod { |budgetPercent = 50, full = 4| addr.sendMsg('/lod', budgetPercent.asFloat, full.asInteger) }

	// ---- level (docs/loudness.md) ----
	// The listening gain, dB -80..80, on top of the level (ramps over 50 ms).
	gain_ { |dB = 0| addr.sendMsg('/gain', dB.asFloat) }
	// --level auto's target for each scene's default rain, LUFS -60..-5 (refused under --level physical).
	loudness_ { |lufs = -23| addr.sendMsg('/loudness', lufs.asFloat) }
	// action.value(event): level (\auto or \physical), target and measured (LUFS), levelGain and gain (dB),
	// fullScaleSPL (what 0 dBFS is now, dB SPL); nil after timeout seconds.
	level { |action, timeout = 2|
		this.query('/loudness', { |msg|
			action.value(msg !? {
				(level: msg[1], target: msg[2], measured: msg[3], levelGain: msg[4], gain: msg[5], fullScaleSPL: msg[6])
			})
		}, timeout)
	}
	surfaceAdd { |name, kind, material, sizeX, sizeY, x, y, z|
		addr.sendMsg('/surface/add', name.asString, kind.asString, material.asString,
			*[sizeX, sizeY, x, y, z].collect(_.asFloat))
	}
	surfaceSet { |name, kind, material, sizeX, sizeY, x, y, z|
		addr.sendMsg('/surface/set', name.asString, kind.asString, material.asString,
			*[sizeX, sizeY, x, y, z].collect(_.asFloat))
	}
	surfaceRemove { |name| addr.sendMsg('/surface/remove', name.asString) }
	quit { addr.sendMsg('/quit') }

	// ---- replies ----
	// action.value once everything sent before has been applied by the audio thread.
	sync { |action|
		var id = nextSyncId;
		nextSyncId = nextSyncId + 1;
		pendingSync[id] = action;
		addr.sendMsg('/sync', id);
		^id
	}
	// In a Routine: waits for /synced (or the timeout, in seconds); true when it came.
	syncWait { |timeout = 2|
		var cond = Condition(false), came = false;
		this.sync({ came = true; cond.test = true; cond.signal });
		SystemClock.sched(timeout, { cond.test = true; cond.signal; nil });
		cond.wait;
		^came
	}

	// action.value(event): the /status.reply fields by name (Ameoto.statusFields), or nil when no
	// reply came within timeout seconds.
	status { |action, timeout = 2|
		var entry = [action, false];
		pendingStatus.add(entry);
		addr.sendMsg('/status');
		SystemClock.sched(timeout, {
			if(pendingStatus.includes(entry)) { pendingStatus.remove(entry); action.value(nil) };
			nil
		});
	}

	// Subscribes (true) or not (false) to periodic /status.reply (onStatus) and /meter (onMeter).
	notify_ { |on = true| addr.sendMsg('/notify', on.binaryValue) }

	version { |action, timeout = 2| this.query('/version', action, timeout, '/version.reply') }

	// A message without arguments and its reply (replyAddress, default ADDRESS.reply as docs/PROTOCOL.md's
	// Queries say), e.g. query('/rain/rate', { |msg| msg.postln }): action.value(msg), or nil after timeout seconds.
	query { |address, action, timeout = 2, replyAddress|
		var answered = false, f;
		f = OSCFunc({ |msg|
			answered = true;
			responders.remove(f);
			action.value(msg)
		}, replyAddress ? (address.asString ++ ".reply").asSymbol, addr).oneShot;
		responders.add(f);
		addr.sendMsg(address);
		SystemClock.sched(timeout, {
			if(answered.not) { f.free; responders.remove(f); action.value(nil) };
			nil
		});
	}

	prStatusReply { |msg|
		var event = ();
		statusFields.do { |name, i| event[name] = msg[i + 1] };
		pendingStatus.copy.do { |entry| pendingStatus.remove(entry); entry[0].value(event) };
		onStatus.value(event);
	}

	prSynced { |id|
		var action = pendingSync.removeAt(id);
		action.value(id);
	}
}
