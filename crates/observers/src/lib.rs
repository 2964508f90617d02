//! State observers for bearing fault diagnosis: APIO, SMO, HOSTSMO, FLO, VSO, PFLO, ALPIO, SMALPIO, ASMO, AFSMO
