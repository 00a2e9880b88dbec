"""inkbsdf: a Mitsuba 3 BSDF for printed ink on paper (see README)."""
