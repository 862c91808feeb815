function [k,T,A,R,c]=orbit_measures(pts,ip)
%% k, period, peak-to-peak of m_y (on the collocation mesh), rms of m_y, drift c
k=arrayfun(@(p)p.parameter(ip.k),pts); T=[pts.period];
A=arrayfun(@(p)max(p.profile(2,:))-min(p.profile(2,:)),pts);
R=arrayfun(@(p)sqrt(trapz(p.mesh,(p.profile(2,:)-trapz(p.mesh,p.profile(2,:))).^2)),pts);
c=arrayfun(@(p)p.parameter(ip.c),pts);
end
