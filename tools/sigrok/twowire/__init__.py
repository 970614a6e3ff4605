##
## twowire-host: libsigrokdecode protocol decoder for Shearwater's 2-wire
## sensor link (SRI-2WIRE-IRD rev E), as driven by the twowire-host core.
##

'''
Shearwater 2-wire sensor link (host <-> sensor on one wire plus ground).

The host powers the sensor with an on-off-keyed ~1 MHz carrier and runs each
transaction as: charge (>= 7 ms carrier), sync (0.9-1.1 ms low), preamble
(1.8-2.2 ms carrier), command (3 or 4 bytes), execute (carrier), listen
(the sensor answers 3 bytes on its own carrier) and a turnaround (low).
Bytes are UART 31.25 kbps 8N2, LSB first, on the envelope: carrier
present = 1 (mark), no carrier = 0.

Channels: 'line' (the wire, required) and optionally 'oe' (the host's output
enable, high while the host drives). With 'oe' the decoder tells host from
peripheral exactly and can time the listen window and the turnaround;
without it, the end of listen is not visible and is not checked.

Sample at 10 MHz or more (the carrier half-period is ~0.5 us).
'''

from .pd import Decoder
