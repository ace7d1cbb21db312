"""``morphkit plan``: a scene planned to an error budget and verified (:mod:`.planrun`), its frames
drawn and measured (:mod:`.planverify`), its report (:mod:`.planreport`) and its shadow
(:mod:`.shadowplanrun`)."""
