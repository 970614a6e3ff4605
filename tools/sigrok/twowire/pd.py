##
## twowire-host: libsigrokdecode protocol decoder for Shearwater's 2-wire
## sensor link (SRI-2WIRE-IRD rev E). See __init__.py and docs/sigrok.md.
##

import sigrokdecode as srd

# annotation classes
A_PHASE, A_HOST, A_PERIPH, A_CMD, A_RESP, A_WARN = range(6)

# decoder states
IDLE, CHARGE, SYNC, PREAMBLE, COMMAND, EXECUTE, LISTEN, TURNAROUND = range(8)
STATE_NAMES = ('Idle', 'Charge', 'Sync', 'Preamble', 'Command', 'Execute',
               'Listen', 'Turnaround')

# spec windows in microseconds (None = no limit)
WINDOWS = {
    CHARGE: (7000, None),
    SYNC: (900, 1100),
    PREAMBLE: (1800, 2200),
    COMMAND: (1000, 1500),
    EXECUTE: (3500, 10000),
    LISTEN: (2000, None),
    TURNAROUND: (2000, None),
}

NAMES = {0x40: 'CONFIG', 0x41: 'FIRMWARE', 0x42: 'REF_VOLTAGE',
         0x43: 'TEMPERATURE', 0x44: 'O2_VOLTAGE', 0x46: 'FIND_FREE',
         0x47: 'FIND_FREE', 0x48: 'READ', 0x49: 'READ', 0x4A: 'ERASE',
         0x4B: 'ERASE'}


def checksum(data):
    return ~sum(data) & 0xFF


def command_name(cmd):
    return 'WRITE' if cmd >= 0x80 else NAMES.get(cmd, 'RESERVED')


def command_detail(frame):
    '''Readable meaning of a whole command frame (without the checksum).'''
    cmd = frame[0]
    name = command_name(cmd)
    if cmd >= 0x80 and len(frame) >= 3:
        addr = (cmd & 0x7F) | ((frame[1] >> 6) << 7)
        data = (frame[1] & 0x3F) << 8 | frame[2]
        return '%s 0x%03X <- 0x%04X' % (name, addr, data)
    if 0x46 <= cmd <= 0x4B:
        return '%s 0x%03X' % (name, (cmd & 1) << 8 | frame[1])
    return name


def hexs(data):
    return ' '.join('%02X' % b for b in data)


class SamplerateError(Exception):
    pass


class Decoder(srd.Decoder):
    api_version = 3
    id = 'twowire'
    name = '2-wire'
    longname = 'Shearwater 2-wire sensor link'
    desc = 'On-off-keyed 1 MHz carrier, UART 31.25 kbps 8N2, host and sensor.'
    license = 'gplv2+'
    inputs = ['logic']
    outputs = []
    tags = ['Embedded/industrial']
    channels = (
        {'id': 'line', 'name': 'LINE', 'desc': 'The 2-wire data line'},
    )
    optional_channels = (
        {'id': 'oe', 'name': 'OE', 'desc': 'Host output enable (high = host drives)'},
    )
    options = (
        {'id': 'gap_us', 'desc': 'Carrier gap that counts as 0 (us)', 'default': 2.0},
        {'id': 'baudrate', 'desc': 'UART bit rate', 'default': 31250},
        {'id': 'execute_max_us', 'desc': 'Longest execute phase (us; 4500 for fw v15)',
         'default': 10000},
    )
    annotations = (
        ('phase', 'Phase'),
        ('host-byte', 'Host byte'),
        ('periph-byte', 'Peripheral byte'),
        ('command', 'Command frame'),
        ('response', 'Response frame'),
        ('warning', 'Warning'),
    )
    annotation_rows = (
        ('phases', 'Phases', (A_PHASE,)),
        ('bytes', 'Bytes', (A_HOST, A_PERIPH)),
        ('frames', 'Frames', (A_CMD, A_RESP)),
        ('warnings', 'Warnings', (A_WARN,)),
    )

    def __init__(self):
        self.reset()

    def reset(self):
        self.samplerate = None
        self.state = IDLE
        self.phase_start = 0
        self.env = 0
        self.last_fall = 0
        self.rx = None
        self.rx_next = None
        self.cmd = []
        self.resp = []
        self.resp_done = False
        self.mark_start = None

    def start(self):
        self.out_ann = self.register(srd.OUTPUT_ANN)

    def metadata(self, key, value):
        if key == srd.SRD_CONF_SAMPLERATE:
            self.samplerate = value

    # ------------------------------------------------------------ helpers
    def ann(self, ss, es, cls, texts):
        self.put(int(ss), int(max(es, ss)), self.out_ann, [cls, texts])

    def warn(self, ss, es, text):
        self.ann(ss, es, A_WARN, [text, 'Warning', 'W'])

    def us(self, samples):
        return samples / self.spu

    def end_phase(self, t, label=None):
        '''Annotates the current phase from its start to t and checks its
        duration against the spec window.'''
        st, ss = self.state, self.phase_start
        name = label or STATE_NAMES[st]
        d = self.us(t - ss)
        self.ann(ss, t, A_PHASE, ['%s %.0f us' % (name, d), name, name[0]])
        lo, hi = WINDOWS.get(st, (None, None))
        if st == EXECUTE:
            hi = self.options['execute_max_us']
        if label is None and ((lo is not None and d < lo) or (hi is not None and d > hi)):
            if hi is None:
                self.warn(ss, t, '%s %.0f us shorter than %d us' % (name, d, lo))
            else:
                self.warn(ss, t, '%s %.0f us outside %d-%d us' % (name, d, lo, hi))

    def goto(self, state, t):
        self.state = state
        self.phase_start = t

    # ------------------------------------------------------------ UART
    def rx_start(self, t, periph):
        self.rx = {'ts': t, 'periph': periph, 'i': 0, 'val': 0}
        self.rx_next = t + self.bit / 2

    def rx_sample(self, level):
        rx = self.rx
        i, ts = rx['i'], rx['ts']
        who = 'peripheral' if rx['periph'] else 'host'
        if i == 0:
            if level:
                self.warn(ts, self.samplenum, 'False start bit (%s)' % who)
                self.rx = None
                return
        elif i <= 8:
            rx['val'] |= level << (i - 1)
        else:
            self.rx = None
            es = ts + 11 * self.bit
            if not level and rx['val'] == 0:
                self.ann(ts, ts + 10 * self.bit, A_PERIPH if rx['periph'] else A_HOST,
                         ['Break', 'Brk', 'B'])
                self.byte_done(None, ts, es)
                return
            if not level:
                self.warn(ts, es, 'Framing error (%s): stop bit 0' % who)
            v = rx['val']
            tag = 'P' if rx['periph'] else 'H'
            self.ann(ts, es, A_PERIPH if rx['periph'] else A_HOST,
                     ['%s: %02X' % (tag, v), '%02X' % v])
            self.byte_done(v, ts, es)
            return
        rx['i'] = i + 1
        self.rx_next = ts + (i + 1.5) * self.bit

    def byte_done(self, value, ss, es):
        if self.state == COMMAND:
            if value is None:
                value = 0
            self.cmd.append((value, ss, es))
            n = 4 if self.cmd[0][0] >= 0x80 else 3
            if len(self.cmd) == n:
                data = [b[0] for b in self.cmd]
                ok = checksum(data[:-1]) == data[-1]
                verdict = 'checksum OK' if ok else \
                    'checksum BAD (expected %02X)' % checksum(data[:-1])
                fss = self.cmd[0][1]
                self.ann(fss, es, A_CMD,
                         ['Command %s: %s, %s' % (hexs(data), command_detail(data), verdict),
                          '%s %s' % (command_name(data[0]), 'OK' if ok else 'BAD'),
                          command_name(data[0])])
                if not ok:
                    self.warn(fss, es, 'Command checksum BAD')
                self.end_phase(es)
                self.goto(EXECUTE, es)
        elif self.state == LISTEN and not self.resp_done:
            if value is None:
                self.resp_done = True     # break: the sensor stopped keying
                return
            self.resp.append((value, ss, es))
            if len(self.resp) == 3:
                self.resp_done = True
                data = [b[0] for b in self.resp]
                ok = checksum(data[:2]) == data[2]
                verdict = 'checksum OK' if ok else \
                    'checksum BAD (expected %02X)' % checksum(data[:2])
                self.ann(self.resp[0][1], es, A_RESP,
                         ['Response %s: 0x%04X, %s' % (hexs(data), data[0] << 8 | data[1], verdict),
                          '0x%04X %s' % (data[0] << 8 | data[1], 'OK' if ok else 'BAD'),
                          '%04X' % (data[0] << 8 | data[1])])
                if not ok:
                    self.warn(self.resp[0][1], es, 'Response checksum BAD')

    def close_listen(self, t, label=None):
        if len(self.resp) < 3:
            ss = self.resp[0][1] if self.resp else self.phase_start
            text = 'No response' if not self.resp else \
                'Short response %s (%d of 3 bytes)' % (hexs(b[0] for b in self.resp), len(self.resp))
            self.ann(ss, t, A_RESP, [text, 'None' if not self.resp else 'Short'])
        self.rx = None
        self.end_phase(t, label)

    # ------------------------------------------------------------ events
    def on_env_rise(self, t):
        st = self.state
        if st == IDLE:
            if self.oe is None or self.oe:
                self.goto(CHARGE, t)
        elif st == SYNC:
            if self.oe is None and self.us(t - self.phase_start) > 10000:
                self.warn(self.phase_start, t, 'Charge not followed by a sync')
                self.goto(CHARGE, t)
                return
            self.end_phase(t)
            self.goto(PREAMBLE, t)
        elif st == LISTEN:
            self.mark_start = t
        elif st == TURNAROUND:      # idle charge: the carrier comes back
            self.end_phase(t)
            self.goto(CHARGE, t)

    def on_env_fall(self, t):
        st = self.state
        if st == CHARGE:
            self.end_phase(t)
            self.goto(SYNC, t)
        elif st == PREAMBLE:
            self.end_phase(t)
            self.goto(COMMAND, t)
            self.cmd = []
            self.rx_start(t, False)
        elif st == COMMAND:
            if self.rx is None:
                self.rx_start(t, False)
        elif st == EXECUTE:
            if self.oe is None:
                self.end_phase(t)
                self.start_listen(t)
        elif st == LISTEN:
            if self.mark_start is None:
                return
            if self.oe is None and self.us(t - self.mark_start) > 1000:
                # a long burst while listening without OE: the next charge
                self.close_listen(self.mark_start, 'Listen/turnaround')
                self.goto(CHARGE, self.mark_start)
                self.end_phase(t)
                self.goto(SYNC, t)
                return
            if self.rx is None and not self.resp_done:
                self.rx_start(t, True)

    def start_listen(self, t):
        self.goto(LISTEN, t)
        self.resp = []
        self.resp_done = False
        self.mark_start = None
        self.rx = None

    def on_oe(self, t, oe):
        st = self.state
        if not oe:
            if st == EXECUTE:
                self.end_phase(t)
                self.start_listen(t)
            elif st == TURNAROUND:
                self.end_phase(t)
                self.goto(IDLE, t)
            elif st in (CHARGE, SYNC, PREAMBLE, COMMAND):
                self.warn(self.phase_start, t,
                          'Host released the line during %s' % STATE_NAMES[st])
                self.rx = None
                self.goto(IDLE, t)
        else:
            if st == LISTEN:
                self.close_listen(t)
                self.goto(TURNAROUND, t)

    # ------------------------------------------------------------ main loop
    def decode(self):
        if not self.samplerate:
            raise SamplerateError('Cannot decode without samplerate.')
        self.spu = self.samplerate / 1e6            # samples per microsecond
        if self.spu < 2:
            raise SamplerateError('Need at least 2 MHz (10 MHz recommended).')
        self.hold = max(1, int(round(self.options['gap_us'] * self.spu)))
        self.half = min(self.hold - 1, int(round(0.5 * self.spu)))
        self.bit = self.samplerate / float(self.options['baudrate'])
        has_oe = self.has_channel(1)

        pins = self.wait({'skip': 1})
        line = pins[0]
        self.oe = pins[1] if has_oe else None
        self.env = line
        self.last_fall = self.samplenum
        while True:
            conds = [{0: 'e'}]
            if has_oe:
                conds.append({1: 'e'})
            deadlines = []
            if line == 0 and self.env:
                deadlines.append(self.last_fall + self.hold)
            if self.rx is not None:
                deadlines.append(self.rx_next)
            if deadlines:
                conds.append({'skip': max(1, int(min(deadlines)) - self.samplenum)})
            pins = self.wait(conds)
            now = self.samplenum
            new_line = pins[0]
            new_oe = pins[1] if has_oe else None
            old_oe, self.oe = self.oe, new_oe
            if new_line != line:
                line = new_line
                if line:
                    if not self.env:
                        self.env = 1
                        self.on_env_rise(now)
                else:
                    self.last_fall = now
            if not line and self.env and now - self.last_fall >= self.hold:
                self.env = 0
                self.on_env_fall(self.last_fall + self.half)
            if has_oe and new_oe != old_oe:
                self.on_oe(now, new_oe)
            if self.rx is not None and now >= self.rx_next:
                level = 1 if (line or now - self.last_fall < self.hold) else 0
                self.rx_sample(level)
